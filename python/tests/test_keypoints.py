"""Detector keypoints from Python: read() of a COCO results file and of an
OpenPose folder (the scores as Tracks.confidence, frames with no person as
a warning), and observation_weights of reconstruct() and refine(), which
are the tool's --confidence_weights."""
import json
import subprocess
import warnings

import numpy as np
import pytest

import nrsfm
from conftest import cli, reprojection


def keypoint_sequence():
    """A superquadric (K = 4) as pixels with v down, and scores: 40 frames,
    30 points; frame 7 has no person."""
    s = nrsfm.synth(dataset="superquadric", frames=40, points=30, seed=3)
    w = s.W.copy()
    w[0::2] = 320 + 300 * w[0::2]
    w[1::2] = 240 - 300 * w[1::2]
    rng = np.random.default_rng(11)
    score = rng.uniform(0.2, 1.0, size=(40, 30))
    score[3, 4] = 0.01  # below the default min_confidence 0.05
    return w, score


def write_coco(path, w, score, no_person=()):
    entries = []
    for t in range(score.shape[0]):
        if t in no_person:
            continue
        keypoints = np.stack([w[2 * t], w[2 * t + 1], score[t]], axis=1).ravel()
        entries.append({"image_id": t, "category_id": 1, "keypoints": keypoints.tolist(),
                        "score": 1.0})
    path.write_text(json.dumps(entries))


def test_read_coco_and_openpose(tmp_path):
    w, score = keypoint_sequence()
    write_coco(tmp_path / "k.json", w, score, no_person=(7,))
    with pytest.warns(nrsfm.NrsfmWarning,
                      match=r"1 of 40 frames have no person, their points are missing "
                            r"\(image_id 7\)"):
        t = nrsfm.read(tmp_path / "k.json")
    assert t.W.shape == (80, 30) and t.cameras == 1
    assert t.confidence.shape == (40, 30)
    assert np.isnan(t.confidence[7]).all() and not t.mask[7].any()
    assert t.confidence[3, 4] == 0.01 and not t.mask[3, 4]
    assert np.isnan(t.W[6:8, 4]).all()
    assert t.mask.sum() == 40 * 30 - 30 - 1
    assert t.W[0, 5] == w[0, 5] and t.W[1, 5] == w[1, 5]  # pixels as written
    np.testing.assert_array_equal(t.confidence[:7], score[:7])

    strict = nrsfm.read(tmp_path / "k.json", min_confidence=0.5)
    assert strict.mask.sum() == np.count_nonzero(np.delete(score, 7, axis=0) >= 0.5)

    folder = tmp_path / "openpose"
    folder.mkdir()
    for t_ in range(40):
        people = [] if t_ == 7 else [{
            "pose_keypoints_2d": np.stack([w[2 * t_], w[2 * t_ + 1], score[t_]],
                                          axis=1).ravel().tolist()}]
        (folder / ("clip_%d_keypoints.json" % t_)).write_text(
            json.dumps({"version": 1.3, "people": people}))
    with pytest.warns(nrsfm.NrsfmWarning, match="clip_7_keypoints.json"):
        o = nrsfm.read(folder)
    np.testing.assert_array_equal(o.W, t.W)
    np.testing.assert_array_equal(o.mask, t.mask)
    np.testing.assert_array_equal(o.confidence, t.confidence)
    # Other formats have no scores.
    assert nrsfm.read(tmp_path / "k.json", format="coco").confidence is not None
    np.savetxt(tmp_path / "w.txt", w)
    assert nrsfm.read(tmp_path / "w.txt").confidence is None


def test_read_errors_are_the_tools(tmp_path):
    (tmp_path / "a.json").write_text('{"annotations": []}')
    with pytest.raises(ValueError, match="this looks like a COCO annotation file"):
        nrsfm.read(tmp_path / "a.json")
    with pytest.raises(ValueError, match='--part: keypoint part: unknown value "feet"'):
        nrsfm.read(tmp_path / "a.json", part="feet")
    with pytest.raises(FileNotFoundError):
        nrsfm.read(tmp_path / "nope.json")


def test_observation_weights(tmp_path):
    w, score = keypoint_sequence()
    write_coco(tmp_path / "k.json", w, score)
    t = nrsfm.read(tmp_path / "k.json")
    plain = nrsfm.reconstruct(t.W, 4, mask=t.mask)
    # Equal weights, any value: the unweighted reconstruction.
    equal = nrsfm.reconstruct(t.W, 4, mask=t.mask, observation_weights=np.full((40, 30), 0.25))
    np.testing.assert_allclose(equal.points_camera, plain.points_camera, rtol=0, atol=1e-8)
    assert equal.summary["options"]["confidence_weights"] == "true"
    assert plain.summary["options"]["confidence_weights"] == "false"
    # The scores: what the tool's --confidence_weights gives.
    weighted = nrsfm.reconstruct(t.W, 4, mask=t.mask, observation_weights=t.confidence)
    np.testing.assert_allclose(reprojection(weighted)[t.mask.repeat(2, axis=0)],
                               t.W[t.mask.repeat(2, axis=0)], atol=1e-6)
    if cli():
        run = subprocess.run([cli(), "reconstruct", "--input", "k.json", "--K", "4", "--output",
                              "o", "--confidence_weights", "--quiet"],
                             cwd=tmp_path, capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        tool = np.loadtxt(tmp_path / "o" / "points_camera.csv", delimiter=",", skiprows=1)
        ours = weighted.points_camera[:, 0].transpose(0, 2, 1).reshape(-1, 3)
        np.testing.assert_allclose(tool[:, 3:], ours, rtol=0, atol=1e-9)
    # refine takes them too: its initial cost is the weighted data term,
    # 1/2 sum of w ||e||^2 with w the scores scaled to average 1 (no extra
    # term: refine uses exactly the term weights given).
    refined = nrsfm.refine(t.W, weighted, mask=t.mask, observation_weights=t.confidence)
    assert refined.summary["observation_weights"] is True
    relative = t.confidence / t.confidence[t.mask].mean()
    e = (reprojection(weighted) - t.W).reshape(40, 2, 30)
    expected = 0.5 * np.sum((relative * (e ** 2).sum(axis=1))[t.mask])
    assert refined.summary["initial_cost"] == pytest.approx(expected, rel=1e-9)
    unweighted = nrsfm.refine(t.W, weighted, mask=t.mask)
    assert unweighted.summary["initial_cost"] == pytest.approx(
        0.5 * np.sum((e ** 2).sum(axis=1)[t.mask]), rel=1e-9)

    with pytest.raises(ValueError, match=r"observation_weights is 3 x 30, expected 40 x 30"):
        nrsfm.reconstruct(t.W, 4, mask=t.mask, observation_weights=np.ones((3, 30)))
    bad = np.ones((40, 30))
    bad[0, 0] = -1
    with pytest.raises(ValueError, match="weights must be finite and >= 0"):
        nrsfm.reconstruct(t.W, 4, mask=t.mask, observation_weights=bad)
    with pytest.raises(ValueError, match="every visible observation has weight 0"):
        nrsfm.reconstruct(t.W, 4, mask=t.mask, observation_weights=np.zeros((40, 30)))
    with pytest.raises(TypeError, match="unexpected keyword argument 'confidence_weights'"):
        nrsfm.reconstruct(t.W, 4, confidence_weights=True)
