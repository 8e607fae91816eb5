"""Every bad input raises ValueError (OSError for a file that cannot be
opened, TypeError for a wrong keyword or type) with the nrsfm tool's
message; none crashes the interpreter."""
import os

import numpy as np
import pytest

import nrsfm
from conftest import cli, cli_error, rotating_w

needs_cli = pytest.mark.skipif(cli() is None, reason="NRSFM_CLI (the nrsfm binary) not set")


def message(function, *args, error=ValueError, **kwargs):
    with pytest.raises(error) as info:
        function(*args, **kwargs)
    return str(info.value)


# (keywords, the tool's flags, the message both give)
OPTION_ERRORS = [
    ({"K": 0}, ["--K", "0"], "--K: must be an integer >= 1 or 'auto', got '0'"),
    ({"K": "many"}, ["--K", "many"], "--K: must be an integer >= 1 or 'auto', got 'many'"),
    ({"init": "best"}, ["--init", "best"], None),
    ({"robust": "tukey"}, ["--robust", "tukey"], None),
    ({"linear_solver": "magic"}, ["--linear_solver", "magic"], None),
    ({"priors": "some"}, ["--priors", "some"], None),
    ({"temporal": -1.0}, ["--temporal", "-1"],
     "--temporal: problem options: term weight temporal must be finite and >= 0, got -1"),
    ({"smoothness": float("nan")}, ["--smoothness", "nan"], None),
    ({"max_iterations": -1}, ["--max_iterations", "-1"], None),
    ({"threads": 0}, ["--threads", "0"], None),
    ({"K_max": 1, "K": "auto"}, ["--K_max", "1", "--K", "auto"],
     "--K_max: K selection: max_num_bases must be >= 2, got 1"),
    ({"K_threshold": 0.5, "K": "auto"}, ["--K_threshold", "0.5", "--K", "auto"],
     "--K_threshold: K selection: threshold must be finite and >= 1, got 0.5"),
]


@pytest.mark.parametrize("keywords,flags,expected", OPTION_ERRORS)
def test_bad_options_raise_value_error(keywords, flags, expected):
    keywords = dict(keywords)
    k = keywords.pop("K", 1)
    text = message(nrsfm.reconstruct, rotating_w(10, 8), k, **keywords)
    if expected is not None:
        assert text == expected
    assert flags[0][2:] in text


@needs_cli
@pytest.mark.parametrize("keywords,flags,expected", OPTION_ERRORS)
def test_bad_options_give_the_tools_message(keywords, flags, expected, tmp_path):
    np.savetxt(tmp_path / "w.txt", rotating_w(10, 8))
    keywords = dict(keywords)
    k = keywords.pop("K", 1)
    if "--K" not in flags:
        flags = flags + ["--K", "1"]
    text = message(nrsfm.reconstruct, rotating_w(10, 8), k, **keywords)
    tool = cli_error(["reconstruct", "--input", "w.txt", "--output", "o"] + flags, tmp_path)
    assert text == tool


def bad_data():
    """(name, W, keywords, part of the message) of data nrsfm cannot take."""
    w = rotating_w(10, 8)
    half_nan = w.copy()
    half_nan[2, 3] = np.nan
    inf = w.copy()
    inf[5, 2] = np.inf
    return [
        ("one coordinate NaN", half_nan, {},
         "W: only one coordinate of the observation at rows 3-4, column 4 (1-based) is NaN; "
         "mark a missing point with NaN in both"),
        ("Inf", inf, {}, "W: infinite value at row 6, column 3 (1-based); use NaN to mark a missing entry"),
        ("odd rows", w[:-1], {}, "W: 19 rows is not a multiple of 2 (expected rows u, v per frame)"),
        ("rows not a multiple of 2M", w[:-2], {"cameras": 2},
         "W: 18 rows is not a multiple of 2 x 2 cameras (expected rows u, v per frame and camera)"),
        ("one frame", rotating_w(1, 8), {},
         "both starts failed: factorization: start: needs at least 2 frames, got F = 1; "
         "rigid: start: needs at least 2 frames, got F = 1"),
        ("two points", rotating_w(10, 2), {},
         "start: K = 1 needs 3K + 1 = 4 points and 2F >= 4; got P = 2, F = 10"),
        ("K too large", w, {"K": 3},
         "start: K = 3 needs 3K + 1 = 10 points and 2F >= 10; got P = 8, F = 10"),
        # (σ₃/σ₁ is round-off, so the needle is the words after it.)
        ("no rotation", np.tile(rotating_w(1, 12), (15, 1)), {},
         "< 1e-06): the sequence shows no rotation (or the object is flat), so depth is "
         "unobservable; rigid: start: rigid start: the centred 2D tracks have rank < 3"),
        ("1-D", w[0], {}, "W must be a 2-D array, got shape (8,)"),
        ("3-D", w[None], {}, "W must be a 2-D array, got shape (1, 20, 8)"),
        ("empty", np.zeros((0, 0)), {}, "W: matrix is empty (0 x 0)"),
        ("strings", [["a", "b"], ["c", "d"]], {},
         "W must be an array of numbers (convertible to float64), got list"),
        ("mask shape", w, {"mask": np.ones((3, 8))},
         "mask is 3 x 8; expected 20 x 8 or 10 x 8 (W is 20 x 8, M = 1)"),
        ("mask NaN", w, {"mask": np.full((10, 8), np.nan)}, "mask holds NaN or Inf; expected 0/1"),
        ("mask u and v differ", w, {"mask": np.eye(20, 8)},
         "mask: rows 1 and 2 (u and v of one view) differ at column 1 (1-based)"),
        ("cameras 0", w, {"cameras": 0}, "cameras must be >= 1, got 0"),
        ("rigidity, one camera", w, {"rigidity": 1.0},
         "W: --rigidity: needs data from M >= 2 synchronised cameras, got M = 1"),
        ("too little left", np.where(np.arange(8) < 5, np.nan, w), {"K": 1},
         "start: too few observations for K = 1: leaving out the 8 points seen in fewer "
         "than 2 views and the 10 frames whose views see fewer than 4 points leaves F = 0, "
         "P = 0 (K = 1 needs F >= 2, 2F >= 4 and P >= 4)"),
    ]


@pytest.mark.parametrize("name,w,keywords,expected", bad_data(), ids=[d[0] for d in bad_data()])
def test_bad_data_raises_value_error(name, w, keywords, expected):
    keywords = dict(keywords)
    k = keywords.pop("K", 1)
    assert expected in message(nrsfm.reconstruct, w, k, **keywords)


@needs_cli
def test_bad_data_gives_the_tools_message_after_its_file_name(tmp_path):
    # What the solver says, the tool says after the input's name.
    for w, k in [(rotating_w(10, 8), 3), (np.tile(rotating_w(1, 12), (15, 1)), 1),
                 (rotating_w(1, 8), 1)]:
        np.savetxt(tmp_path / "w.txt", w)
        text = message(nrsfm.reconstruct, w, k)
        tool = cli_error(["reconstruct", "--input", "w.txt", "--K", str(k), "--output", "o"],
                         tmp_path)
        assert tool == "w.txt: " + text


def test_wrong_keywords_and_types_raise_type_error():
    w = rotating_w(10, 8)
    assert message(nrsfm.reconstruct, w, 1, error=TypeError, inti="rigid") == \
        "reconstruct() got an unexpected keyword argument 'inti'"
    # The input file's and the tool's own flags are not keywords here.
    for flag in ("input", "var", "output", "quiet", "truth", "cameras_from_file"):
        assert "unexpected keyword argument '%s'" % flag in \
            message(nrsfm.reconstruct, w, 1, error=TypeError, **{flag: "x"})
    assert "unexpected keyword argument 'init'" in \
        message(nrsfm.refine, w, {}, error=TypeError, init="rigid")
    assert message(nrsfm.reconstruct, w, 1, error=TypeError, max_iterations=2.5) == \
        "max_iterations must be an int, got float"
    assert message(nrsfm.reconstruct, w, 1, error=TypeError, init=3) == \
        "init must be a str, got int"
    assert message(nrsfm.reconstruct, w, 1, error=TypeError, smoothness="a lot") == \
        "smoothness must be a float, got str"
    assert message(nrsfm.reconstruct, w, True, error=TypeError) == "K must be an int, got bool"
    assert message(nrsfm.reconstruct, w, 1, error=ValueError, seed=-1) == \
        "seed must be an integer in [0, 2^64)"
    # numpy scalars are numbers.
    r = nrsfm.reconstruct(rotating_w(12, 8), np.int64(1), max_iterations=np.int32(3),
                          robust_scale=np.float32(2.0))
    assert r.summary["options"]["max_iterations"] == "3"


@pytest.mark.filterwarnings("ignore::nrsfm.NrsfmWarning")
def test_an_unusable_refinement_raises_with_the_start_attached():
    with pytest.raises(ValueError, match="the refinement did not give a usable solution") as info:
        nrsfm.reconstruct(rotating_w(10, 8) * 1e300, 1)
    start = info.value.result
    assert isinstance(start, nrsfm.Reconstruction)
    assert start.summary["solution_usable"] is False
    assert any("not usable" in warning for warning in start.summary["warnings"])


def test_refine_rejects_a_model_that_does_not_fit():
    s = nrsfm.synth(dataset="random", frames=20, points=10, K=2, seed=1)
    t = s.truth
    good = {"rotations": t.rotations, "translations": t.translations, "weights": t.weights,
            "basis": t.basis}

    def with_(**changes):
        model = dict(good)
        model.update(changes)
        return message(nrsfm.refine, s.W, model)

    assert with_(basis=t.basis[:, :, :9]) == "model.basis has shape (2, 3, 9), expected (2, 3, 10)"
    assert with_(weights=t.weights[:19]) == \
        "model.weights has shape (19, 2), expected (20, K) for the F = 20 frames of W"
    assert with_(translations=t.translations[..., :1]) == \
        "model.translations has shape (20, 1, 1), expected (20, 1, 2)"
    bent = t.rotations.copy()
    bent[3, 0, 0, 0] = 2.0
    assert with_(rotations=bent) == "model.rotations[3, 0] is not a rotation matrix " \
        "(R R^T = I and det R = +1 to 1e-6)"
    assert with_(scales=np.ones((20, 2))) == "model.scales has shape (20, 2), expected (20, 1)"
    assert "model.basis must be an array of numbers" in with_(basis="basis")
    nan_basis = t.basis.copy()
    nan_basis[0, 0, 0] = np.nan
    assert "refine: model: basis has a NaN or infinite value" in with_(basis=nan_basis)
    assert message(nrsfm.refine, s.W, {"rotations": t.rotations}) == \
        "model must have rotations, translations, weights and basis (attributes or keys)"
    assert message(nrsfm.refine, s.W, object()) == \
        "model must have rotations, translations, weights and basis (attributes or keys)"


def test_read_raises_os_error_for_files_that_cannot_be_opened(tmp_path):
    with pytest.raises(FileNotFoundError) as info:
        nrsfm.read(tmp_path / "nope.mat")
    assert str(info.value) == str(tmp_path / "nope.mat") + ": no such file"
    # A folder is read as OpenPose's folder of frames; one named .mat is not.
    (tmp_path / "d.mat").mkdir()
    with pytest.raises(IsADirectoryError):
        nrsfm.read(tmp_path / "d.mat")
    with pytest.raises(ValueError, match="no .json files in the folder"):
        nrsfm.read(tmp_path)
    if os.geteuid() != 0:  # root reads anything
        locked = tmp_path / "locked.txt"
        np.savetxt(locked, rotating_w(10, 8))
        locked.chmod(0)
        with pytest.raises(PermissionError):
            nrsfm.read(locked)
    with pytest.raises(TypeError, match="path must be a path"):
        nrsfm.read(3)


def test_read_raises_value_error_for_bad_contents(tmp_path):
    (tmp_path / "noise.mat").write_bytes(bytes(range(256)) * 16)
    assert "not a MATLAB .mat file" in message(nrsfm.read, tmp_path / "noise.mat")
    (tmp_path / "token.txt").write_text("1 2 3\n4 x3 6\n")
    assert message(nrsfm.read, str(tmp_path / "token.txt")) == \
        str(tmp_path / "token.txt") + ": line 2, column 2: 'x3' is not a number"
    (tmp_path / "w.dat").write_text("1 2\n3 4\n")
    (tmp_path / "w.txtx").write_text("1 2\n3 4\n")
    assert "cannot tell the input format" in message(nrsfm.read, tmp_path / "w.txtx")
    assert message(nrsfm.read, tmp_path / "w.dat", format="xml") == \
        '--format: input format: unknown value "xml" (expected one of auto, mat, text, list, ' \
        'coco, openpose)'


def test_read_takes_the_cameras_from_the_file_and_names_both_counts(tmp_path):
    path = tmp_path / "shoe.mat"
    nrsfm.synth(dataset="shoe", frames=20, output=str(path))
    assert nrsfm.read(path).cameras == 1
    assert message(nrsfm.read, path, cameras=2) == \
        str(path) + ": the file records cameras = 1 (variable 'cameras') but 2 camera(s) " \
        "were asked for"


@needs_cli
def test_read_gives_the_tools_message(tmp_path):
    nrsfm.synth(dataset="shoe", frames=20, output=str(tmp_path / "shoe.mat"))
    for path, keywords, flags in [("nope.mat", {}, []), ("shoe.mat", {"cameras": 2},
                                                         ["--cameras", "2"])]:
        with pytest.raises((OSError, ValueError)) as info:
            nrsfm.read(path if os.path.isabs(path) else str(tmp_path / path), **keywords)
        tool = cli_error(["reconstruct", "--input", str(tmp_path / path), "--K", "1",
                          "--output", "o"] + flags, tmp_path)
        assert str(info.value) == tool


def test_synth_and_evaluate_errors():
    assert message(nrsfm.synth, dataset="teapot") == \
        '--dataset: unknown value "teapot" (expected one of random, superquadric, shoe, reproject)'
    assert message(nrsfm.synth, output="x.txt") == "--output must name a .mat file, got 'x.txt'"
    assert message(nrsfm.synth, dataset="shoe", K=3) == "--K is fixed (4) for the shoe dataset"
    assert "frames" in message(nrsfm.synth, frames=1)
    assert message(nrsfm.synth, error=TypeError, colour="red") == \
        "synth() got an unexpected keyword argument 'colour'"
    truth = np.random.default_rng(0).standard_normal((4, 3, 5))
    assert message(nrsfm.evaluate, truth, truth[:3]) == \
        "evaluation: truth has 4 frames, estimate has 3"
    assert message(nrsfm.evaluate, truth, truth[:, :2]) == \
        "result has shape (4, 2, 5), expected (F, 3, P)"
    with pytest.raises(FileNotFoundError):
        nrsfm.evaluate("nope.mat", truth)
