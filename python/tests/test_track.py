"""nrsfm.track(): frames as an array, queries as an array or a CSV file."""
import os

import numpy as np
import pytest

import nrsfm


def blob_frames(frames=12, height=96, width=128, step=(1.5, 0.75), seed=3):
    """A texture of Gaussian blobs that moves by `step` pixels (x, y) per
    frame, and the function that gives a texture point's true position."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-20, 180, size=(120, 2))
    sigmas = rng.uniform(2.5, 6.0, size=120)
    signs = rng.choice([-1.0, 1.0], size=120)
    yy, xx = np.mgrid[0:height, 0:width].astype(float)
    video = np.empty((frames, height, width), dtype=np.uint8)
    for t in range(frames):
        image = np.full((height, width), 128.0)
        for (cx, cy), s, a in zip(centres, sigmas, signs):
            cx, cy = cx + step[0] * t, cy + step[1] * t
            image += 90 * a * np.exp(-((xx - cx) ** 2 + (yy - cy) ** 2) / (2 * s * s))
        video[t] = np.clip(np.round(image), 0, 255)
    return video, lambda x, y, t: (x + step[0] * t, y + step[1] * t)


def test_a_moving_texture_is_tracked_to_a_fraction_of_a_pixel():
    video, truth = blob_frames()
    queries = np.array([[p, 0, x, y] for p, (x, y) in
                        enumerate([(40, 30), (64, 48), (80, 40), (50, 60)])], float)
    for method in ("rank", "lk"):
        t = nrsfm.track(video, queries, track_method=method)
        assert t.W.shape == (2 * 12, 4) and t.mask.shape == (12, 4)
        assert t.positions.shape == (12, 4, 2)
        assert list(t.point_ids) == [0, 1, 2, 3] and list(t.frame_ids) == list(range(12))
        errors = [np.hypot(*(t.positions[f, p] - np.array(truth(x, y, f))))
                  for p, (_, _, x, y) in enumerate(queries) for f in range(12)]
        # A translation of a well-textured image: both methods within 0.3 px
        # (measured: rank 0.02, lk 0.02 px worst).
        assert max(errors) < 0.3, (method, max(errors))
        assert t.mask[:, :].mean() > 0.9


def test_queries_from_a_file_and_bad_queries(tmp_path):
    video, _ = blob_frames(frames=4)
    path = tmp_path / "q.csv"
    path.write_text("point,frame,x,y\n5,1,40,30\n")
    t = nrsfm.track(video, str(path))
    assert list(t.point_ids) == [5]
    assert np.isnan(t.positions[0, 0]).all()  # before its query frame
    with pytest.raises(ValueError, match="query of point 5: frame 9 is not one of"):
        nrsfm.track(video, np.array([[5, 9, 40, 30]], float))
    with pytest.raises(ValueError, match="outside the 128 x 96 image"):
        nrsfm.track(video, np.array([[5, 0, 400, 30]], float))
    with pytest.raises(ValueError, match=r"expected an \(N, 4\) array"):
        nrsfm.track(video, np.zeros((2, 3)))
    with pytest.raises(ValueError, match="frames: expected a folder"):
        nrsfm.track(np.zeros((4, 5), dtype=np.uint8))
    with pytest.raises(ValueError, match="patch_size: 4"):
        nrsfm.track(video, patch_size=4)
    with pytest.raises(TypeError):
        nrsfm.track(video, smoothness=1.0)
    with pytest.raises(OSError):
        nrsfm.track(os.path.join(str(tmp_path), "missing"))
