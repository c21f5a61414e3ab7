"""The scanfill Python module (issue 14): results equal the CLI's, options are checked as the config's keys, errors
carry the CLI's message, the run releases the GIL, and output.ply opens in Open3D with its colours.

Run by ctest (tests/CMakeLists.txt), which sets PYTHONPATH to the module's folder and SCANFILL_BINARY to the CLI.
Sizes are small (6000 samples, a 200 x 200 scan) so the whole file runs in well under a minute on 2 cores.
"""

import itertools
import os
import pathlib
import subprocess
import threading
import time

import numpy as np
import pytest

import scanfill

CLI = os.environ.get("SCANFILL_BINARY", str(pathlib.Path(scanfill.__file__).resolve().parent.parent / "scanfill"))
SAMPLES = 6000


def cli(*args, check=True):
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, check=check)


def float_ply(path):
    """The vertex table of a binary PLY whose properties are all floats (`scanfill scan`'s x y z nx ny nz), as the
    file has it: read() gives scanfill's view, with normals renormalised in double."""
    data = pathlib.Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    assert "format binary_little_endian 1.0" in header
    first = header.index(next(line for line in header if line.startswith("element vertex")))
    vertex = itertools.takewhile(lambda line: not line.startswith(("element", "end_header")), header[first + 1:])
    names = [line.split()[2] for line in vertex if line.startswith("property float ")]
    n = int(next(line.split()[2] for line in header if line.startswith("element vertex")))
    return np.frombuffer(data, dtype="<f4", count=n * len(names), offset=end).reshape(n, len(names)), names


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    """A one-sided virtual scan of the vase (as `scanfill scan` makes it) and the CLI's completion of it."""
    d = tmp_path_factory.mktemp("scanfill")
    cli("scan", "--input", "procedural:vase", "--output", d / "scan.ply", "--eye", "0,-3,0.6", "--target", "0,0,0.5",
        "--resolution", "200,200", "--fov", "30")
    (d / "vase.yaml").write_text(
        "mode: completion\n"
        "inputs:\n  scan: scan.ply\n  template: procedural:vase_template\n"
        f"output:\n  dir: {d / 'cli'}\n"
        f"sample:\n  count: {SAMPLES}\n")
    cli("--config", d / "vase.yaml", "-q")
    return d


@pytest.fixture(scope="module")
def completed(work):
    """The same completion from numpy arrays, run in a thread while this one keeps counting: the GIL is released."""
    table, names = float_ply(work / "scan.ply")
    assert names == ["x", "y", "z", "nx", "ny", "nz"]
    scan = {"points": table[:, :3].astype(np.float64), "normals": table[:, 3:].astype(np.float64)}
    got = {}

    def complete():
        try:
            got["result"] = scanfill.complete({"points": scan["points"], "normals": scan["normals"]},
                                              "procedural:vase_template", sample={"count": SAMPLES},
                                              output={"dir": str(work / "python")})
        except Exception as e:  # re-raised below, in the test's own thread
            got["error"] = e

    worker = threading.Thread(target=complete)
    ticks = 0
    start = time.monotonic()
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.005)
    got["ticks"], got["seconds"] = ticks, time.monotonic() - start
    if "error" in got:
        raise got["error"]
    return got


def test_read_returns_arrays_in_file_order(work):
    scan = scanfill.read(work / "scan.ply")
    assert scan["points"].dtype == np.float64 and scan["points"].shape[1] == 3
    assert scan["normals"].shape == scan["points"].shape
    assert "faces" not in scan
    table, _ = float_ply(work / "scan.ply")
    assert np.array_equal(scan["points"], table[:, :3])  # in file order, float32 values exactly
    raw = table[:, 3:].astype(np.float64)
    assert np.allclose(scan["normals"], raw / np.linalg.norm(raw, axis=1, keepdims=True), rtol=0, atol=1e-15)
    info = cli("info", "--full", "--json", work / "scan.ply").stdout
    assert f'"points": {len(scan["points"])}' in info
    mesh = scanfill.read("procedural:vase_template")
    assert mesh["faces"].shape[1] == 3 and mesh["faces"].dtype == np.int32
    assert mesh["faces"].max() < len(mesh["points"])


def test_complete_from_arrays_matches_the_cli(work, completed):
    result = completed["result"]
    # The same bytes as the CLI's output.ply, and the arrays are that file's.
    assert (work / "python" / "output.ply").read_bytes() == (work / "cli" / "output.ply").read_bytes()
    assert (work / "python" / "analogy.ply").read_bytes() == (work / "cli" / "analogy.ply").read_bytes()
    n = result["report"]["output"]["points"]
    assert result["points"].shape == (n, 3) and result["normals"].shape == (n, 3)
    assert result["origin"].shape == (n,) and result["label"].shape == (n,) and result["colors"].shape == (n, 3)
    # The scan's points come through unchanged (completion works in the scan's frame).
    scan = scanfill.read(work / "scan.ply")
    assert np.count_nonzero(result["origin"] == 0) == len(scan["points"])
    assert np.count_nonzero(result["origin"] == 1) == result["report"]["output"]["synthesized_points"]
    assert result["report"]["mode"] == "completion"
    assert len(result["analogy"]["label"]) == result["report"]["inputs"]["template"]["samples"]


def test_the_run_releases_the_gil(completed):
    # Held for the whole run, this thread would not have run at all; released, it ticks every ~5 ms.
    assert completed["seconds"] > 0.2
    assert completed["ticks"] >= 0.2 * completed["seconds"] / 0.005


def test_output_opens_in_open3d_with_colours(work, completed):
    o3d = pytest.importorskip("open3d")
    cloud = o3d.io.read_point_cloud(str(work / "python" / "output.ply"))
    result = completed["result"]
    assert cloud.has_points() and cloud.has_normals() and cloud.has_colors()
    assert np.array_equal(np.asarray(cloud.points), result["points"])
    # By origin: scan grey, synthesised orange, copied blue.
    palette = np.array([[190, 190, 190], [235, 130, 35], [60, 120, 225]]) / 255.0
    assert np.allclose(np.asarray(cloud.colors), palette[result["origin"]])
    assert np.array_equal(result["colors"], np.rint(palette[result["origin"]] * 255).astype(np.uint8))


@pytest.mark.parametrize("options, key", [
    ({"sample": {"count": "abc"}}, "sample.count"),
    ({"sample.count": -5}, "sample.count"),
    ({"sample": {"cuont": 5}}, "sample.cuont"),
    ({"smaple": {"count": 5}}, "smaple"),
    ({"output": {"colour": "purple"}}, "output.colour"),
])
def test_a_bad_option_raises_value_error_naming_the_key(options, key):
    with pytest.raises(ValueError, match=key.replace(".", r"\.")) as raised:
        scanfill.complete("procedural:vase", "procedural:vase_template", **options)
    assert isinstance(raised.value, scanfill.ConfigError) and isinstance(raised.value, scanfill.Error)


def test_the_message_is_the_clis(work):
    with pytest.raises(ValueError) as raised:
        scanfill.complete(work / "scan.ply", "procedural:vase_template", sample={"count": "abc"})
    run = cli("--config", work / "vase.yaml", "--set", "sample.count=abc", check=False)
    assert run.returncode == 2
    assert run.stderr.strip() == f"scanfill: error: {raised.value}"


def test_bad_inputs_raise_value_error_naming_them(tmp_path):
    with pytest.raises(ValueError, match=r"inputs\.template: no such file"):
        scanfill.complete("procedural:vase", tmp_path / "missing.ply")
    with pytest.raises(ValueError, match="scan points: expected an N x 3 array"):
        scanfill.complete(np.zeros((10, 2)), "procedural:vase_template")
    with pytest.raises(ValueError, match="template: .*got a list"):
        scanfill.complete("procedural:vase", [[0, 0, 0]])
    with pytest.raises(ValueError, match="mode"):
        scanfill.analogy("procedural:box", "procedural:box_l", mode="completion")


def test_a_run_error_raises_scanfill_error(tmp_path):
    (tmp_path / "taken").write_text("a file where the output folder should be")
    with pytest.raises(scanfill.Error) as raised:
        scanfill.analogy("procedural:box", "procedural:box_l", output={"dir": str(tmp_path / "taken")},
                         sample={"count": 2000})
    assert isinstance(raised.value, RuntimeError) and "taken" in str(raised.value)


def test_analogy_returns_the_target_samples_labelled():
    result = scanfill.analogy("procedural:box", "procedural:box_l", sample={"spacing": 0.05},
                              **{"vote.allow_scale": False})
    n = result["report"]["inputs"]["target"]["samples"]
    assert result["points"].shape == (n, 3) and result["label"].shape == (n,)
    assert result["curvatures"].shape == (n, 2) and result["colors"].dtype == np.uint8
    transforms = result["report"]["transforms"]
    assert {t["label"] for t in transforms} >= set(np.unique(result["label"]).tolist())
    # The L's two boxes: one source box explains both, by two similarity transforms.
    assert sum(t["kind"] == "similarity" and t["labelled"] > 0 for t in transforms) >= 2


def test_scan_fragments_as_a_list_of_a_path_and_an_array(work):
    for name, eye in [("front.ply", "0,-3,0.6"), ("side.ply", "3,0,0.6")]:
        cli("scan", "--input", "procedural:vase", "--output", work / name, "--eye", eye, "--target", "0,0,0.5",
            "--resolution", "100,100")
    (work / "fragments.yaml").write_text(
        "mode: completion\ninputs:\n  scan: [front.ply, side.ply]\n  template: procedural:vase_template\n"
        f"output:\n  dir: {work / 'cli_fragments'}\nsample:\n  count: 2000\n")
    cli("--config", work / "fragments.yaml", "-q")
    table, _ = float_ply(work / "side.ply")
    side = {"points": table[:, :3].astype(np.float64), "normals": table[:, 3:].astype(np.float64)}
    result = scanfill.complete([work / "front.ply", side], "procedural:vase_template", sample={"count": 2000},
                               output={"dir": str(work / "python_fragments")})
    assert (work / "python_fragments" / "output.ply").read_bytes() == \
        (work / "cli_fragments" / "output.ply").read_bytes()
    assert np.count_nonzero(result["origin"] == 0) == len(table) + len(scanfill.read(work / "front.ply")["points"])
