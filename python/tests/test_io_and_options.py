"""nrsfm.read for every input format, nrsfm.synth's file, nrsfm.evaluate with
the tool's numbers, and the keyword options: the tool's flags, declared once."""
import json
import re
import subprocess

import numpy as np
import pytest

import nrsfm
from conftest import cli, rotating_w

needs_cli = pytest.mark.skipif(cli() is None, reason="NRSFM_CLI (the nrsfm binary) not set")


def test_read_every_format_gives_the_same_tracks(tmp_path):
    s = nrsfm.synth(dataset="random", frames=12, points=9, K=2, missing=0.2, seed=8,
                    output=str(tmp_path / "r.mat"))
    from_mat = nrsfm.read(tmp_path / "r.mat")
    assert np.array_equal(from_mat.W, s.W, equal_nan=True)
    assert np.array_equal(from_mat.mask, s.mask)
    # Text: one row of W per line, NaN = missing.
    np.savetxt(tmp_path / "w.csv", s.W, delimiter=",")
    from_text = nrsfm.read(str(tmp_path / "w.csv"))
    assert np.array_equal(from_text.W, s.W, equal_nan=True)
    # Observation list: frame camera point u v per visible entry.
    with open(tmp_path / "w.obs", "w") as f:
        for t, p in zip(*np.nonzero(s.mask)):
            f.write("%d 0 %d %.17g %.17g\n" % (t, p, s.W[2 * t, p], s.W[2 * t + 1, p]))
    from_list = nrsfm.read(tmp_path / "w.obs")
    assert np.array_equal(from_list.W, s.W, equal_nan=True)
    assert np.array_equal(from_list.mask, s.mask)
    assert from_list.frame_ids is None and from_list.point_ids is None
    # The other variables of a .mat file.
    p3 = nrsfm.read(tmp_path / "r.mat", var="P3_gt")
    assert p3.W.shape == (24, 9) and p3.mask.all()
    with pytest.raises(ValueError, match="no variable 'Q'"):
        nrsfm.read(tmp_path / "r.mat", var="Q")


def test_a_list_too_sparse_for_its_indices_keeps_the_frames_and_points_it_mentions(tmp_path):
    # Frame 1 300 000 would make a W of 2 GB: the list's two frames and two
    # points are read, with their indices (core/io/text_io.h).
    path = tmp_path / "two.obs"
    path.write_text("0 0 0 1 2\n1300000 0 99 1.0 2.0\n")
    t = nrsfm.read(path)
    assert t.W.shape == (4, 2)
    assert t.frame_ids == [0, 1300000] and t.point_ids == [0, 99]
    assert t.mask.tolist() == [[True, False], [False, True]]
    assert t.W[2:, 1].tolist() == [1.0, 2.0]


def test_two_camera_files_record_their_cameras(tmp_path):
    path = str(tmp_path / "two.mat")
    s = nrsfm.synth(dataset="shoe", frames=10, cameras=2, output=path)
    t = nrsfm.read(path)
    assert t.cameras == 2 and t.W.shape == (40, 110) and t.mask.shape == (20, 110)
    assert np.array_equal(t.W, s.W, equal_nan=True)
    assert repr(t) == "<nrsfm.Tracks F=10 M=2 P=110>"


@needs_cli
def test_evaluate_gives_the_tools_numbers(tmp_path):
    truth = str(tmp_path / "s.mat")
    nrsfm.synth(dataset="random", frames=40, points=15, K=2, noise=0.01, output=truth)
    subprocess.run([cli(), "reconstruct", "--input", truth, "--K", "2", "--output",
                    str(tmp_path / "out"), "--quiet"], check=True, capture_output=True)
    tool = subprocess.run([cli(), "evaluate", "--truth", truth, "--result",
                           str(tmp_path / "out")], check=True, capture_output=True, text=True)
    expected = json.loads(tool.stdout)
    assert nrsfm.evaluate(truth, tmp_path / "out") == expected
    assert nrsfm.evaluate(truth, str(tmp_path / "out" / "points_camera.csv"))["e3d"] == \
        expected["e3d"]
    # The same reconstruction in Python scores the same.
    t = nrsfm.read(truth)
    r = nrsfm.reconstruct(t.W, 2, mask=t.mask)
    ours = nrsfm.evaluate(truth, r)
    assert ours.keys() == expected.keys()
    assert ours["e3d"] == pytest.approx(expected["e3d"], rel=1e-9)
    # Arrays of shapes (F, 3, P): the camera frame.
    assert nrsfm.evaluate(r.points_camera[:, 0], r)["e3d"] < 1e-12


def test_evaluate_takes_synths_tracks_as_the_truth(tmp_path):
    path = str(tmp_path / "s.mat")
    s = nrsfm.synth(dataset="random", frames=30, points=12, K=1, seed=9, output=path)
    r = nrsfm.reconstruct(s.W, 1)
    assert nrsfm.evaluate(s, r) == nrsfm.evaluate(s.truth, r)
    # P3_gt (3F, P), rows x of every frame, then y, then z: the same truth.
    p3 = s.P3_gt.reshape(3, 30, 12).transpose(1, 0, 2)
    assert nrsfm.evaluate(p3, r)["e3d"] == pytest.approx(nrsfm.evaluate(s, r)["e3d"], rel=1e-9)
    assert nrsfm.evaluate(path, r)["e3d"] == pytest.approx(nrsfm.evaluate(s, r)["e3d"], rel=1e-9)
    with pytest.raises(ValueError, match="these Tracks have no truth"):
        nrsfm.evaluate(nrsfm.read(path), r)


def tool_flags():
    """{flag: (type, default)} from `nrsfm --help`."""
    text = subprocess.run([cli(), "--help"], capture_output=True, text=True).stdout
    text = re.sub(r"\s+", " ", text)
    flags = {}
    for name, kind, default in re.findall(r" -(\w+) \(.*?\) type: (\w+) default: (\S+)", text):
        flags[name] = (kind, default.strip('"'))
    return flags


def python_value(kind, text):
    if kind in ("int32", "uint64"):
        return int(text)
    if kind == "double":
        return float(text)
    if kind == "bool":
        return text == "true"
    return text


@needs_cli
def test_keywords_are_the_tools_flags_with_its_defaults():
    flags = tool_flags()
    assert len(flags) > 30
    for function, table in nrsfm.OPTIONS.items():
        for name, option in table.items():
            assert name in flags, (function, name)
            kind, default = flags[name]
            if function == "synth" and name == "K":
                continue  # an int here, a string flag there
            assert option["default"] == python_value(kind, default), (function, name)
            assert option["help"], (function, name)
    # Every reconstruct flag that is not about the tool's files is a keyword.
    reconstruct = set(nrsfm.OPTIONS["reconstruct"])
    for name in ("init", "priors", "robust", "robust_scale", "max_iterations", "threads",
                 "linear_solver", "seed", "K_max", "K_threshold", "function_tolerance",
                 "cg_tolerance", "rule_min_track_order", "completion_iterations"):
        assert name in reconstruct
    # One weight per extra term (the flags --help lists after the others).
    terms = [name for name, (kind, _) in flags.items()
             if "weight of the" in nrsfm.OPTIONS["reconstruct"].get(name, {}).get("help", "")]
    assert len(terms) >= 7 and {"smoothness", "deformation", "temporal_shape"} <= set(terms)
    for name in terms:
        assert name in set(nrsfm.OPTIONS["refine"])
    assert set(nrsfm.OPTIONS["refine"]) < reconstruct
    assert set(nrsfm.OPTIONS["read"]) == {"cameras", "var", "mask_var", "format", "frame_key",
                                          "part", "min_confidence", "intrinsics"}
    # How a file is read, and weights from a file's scores, are not options
    # of a reconstruction of arrays (observation_weights is an argument).
    for name in nrsfm.OPTIONS["read"].keys() | {"confidence_weights"}:
        assert name not in reconstruct


def test_docstrings_describe_every_keyword():
    for function, table in nrsfm.OPTIONS.items():
        doc = getattr(nrsfm, function).__doc__
        assert doc.startswith(function + "("), function
        for name, option in table.items():
            assert "    %s: " % name in doc, (function, name)
            assert option["help"] in doc, (function, name)
    assert "(F, M, 3, 3)" in nrsfm.reconstruct.__doc__
    assert "Levenberg-Marquardt iterations." in nrsfm.reconstruct.__doc__
    assert nrsfm.__version__


def test_reconstruct_takes_what_read_gives(tmp_path):
    path = str(tmp_path / "q.mat")
    nrsfm.synth(dataset="superquadric", frames=40, points=30, output=path)
    t = nrsfm.read(path)
    r = nrsfm.reconstruct(t.W, 4, mask=t.mask, cameras=t.cameras)
    # Noise-free: measured 1.2e-10 % (2026-11-27); the bound leaves room for
    # where the stopping rule (a relative cost change) ends.
    assert nrsfm.evaluate(path, r)["error3d_pct"] < 1e-6


def test_synth_reproject_writes_its_truth_and_evaluate_scores_the_object_frame(tmp_path):
    source = nrsfm.synth(dataset="random", frames=60, points=20, K=2, seed=3,
                         output=str(tmp_path / "r.mat"))
    assert source.truth is not None
    tracks = nrsfm.synth(dataset="reproject", input=str(tmp_path / "r.mat"), rotation=120,
                         profile="ramp", output=str(tmp_path / "rp.mat"))
    assert tracks.W.shape == (120, 20)
    assert tracks.truth == str(tmp_path / "rp.mat")
    result = nrsfm.reconstruct(tracks.W, 2)
    scores = nrsfm.evaluate(tracks, result)
    assert scores["e3d_frame"] == "object"
    assert "rotation_error" in scores
    assert scores["e3d_camera"] < 1e-6
    with pytest.raises(ValueError, match="needs output="):
        nrsfm.synth(dataset="reproject", input=str(tmp_path / "r.mat"))
    with pytest.raises(ValueError, match="--axis must be three numbers"):
        nrsfm.synth(dataset="reproject", input=str(tmp_path / "r.mat"), axis="1,2",
                    output=str(tmp_path / "x.mat"))
