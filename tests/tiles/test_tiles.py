"""scanfill plan / split / apply (issue 13 item 3): the tiles' outputs and the plan-level points are the one-process
run's output.ply as a set of points, with a scan's own colours and intensity too; apply is the same at 1 and 2
threads; bad plans and tiles are refused with one line naming the file, a non-zero exit and no output."""
import pathlib

import numpy as np
import pytest

from tiles_util import SMALL, VASE, driver, scanfill, single_run


@pytest.fixture(scope="module")
def planned(tmp_path_factory):
    d = tmp_path_factory.mktemp("tiles")
    single = single_run(d / "single", threads=2)
    scanfill("plan", "--config", VASE, *SMALL, "--output", d / "vase.plan", "--threads", 1, "--quiet")
    scanfill("split", "--config", VASE, *SMALL, "--tiles", 4, "--output-dir", d / "tiles", "--quiet")
    return d, single


def test_the_tiles_and_the_plan_points_are_the_single_process_output(planned):
    d, single = planned
    tiles = sorted((d / "tiles").glob("tile_*.ply"))
    assert [t.name for t in tiles] == [f"tile_{i:04d}.ply" for i in range(4)]
    outputs = []
    for t in tiles:
        scanfill("apply", "--plan", d / "vase.plan", "--input", t, "--output", d / "out" / t.name, "--quiet")
        outputs.append(d / "out" / t.name)
    plan_points = d / "plan_points.ply"
    assert len(driver.read_ply(plan_points)[0]) > 0  # the template's copies, emitted once, by the plan
    counts = [len(driver.read_ply(o)[0]) for o in outputs]
    assert min(counts) > 0
    merged = d / "merged.ply"
    total = driver.merge_ply(merged, outputs + [plan_points])
    assert total == len(driver.read_ply(single)[0])
    assert driver.same_points(merged, single)
    # And the comparison can tell: one tile left out is not the same.
    driver.merge_ply(d / "short.ply", outputs[1:] + [plan_points])
    assert not driver.same_points(d / "short.ply", single)


def applied_and_merged(d, plan, plan_points, tiles):
    """Every tile through the plan, merged with the plan-level points."""
    outputs = []
    for t in tiles:
        scanfill("apply", "--plan", plan, "--input", t, "--output", d / "out" / t.name, "--quiet")
        outputs.append(d / "out" / t.name)
    merged = d / "merged.ply"
    driver.merge_ply(merged, outputs + [plan_points])
    return merged


def test_a_coloured_scan_tiled_is_the_single_process_output_colours_and_intensity_too(tmp_path):
    # The small vase's scan as the run loads it, with a colour and an intensity naming each point, as a scan file.
    d = tmp_path
    scanfill("split", "--config", VASE, *SMALL, "--tiles", 1, "--output-dir", d / "whole", "--quiet")
    vertices, _, lines = driver.read_ply(d / "whole" / "tile_0000.ply")
    n = len(vertices)
    dtype = np.dtype(vertices.dtype.descr + [("red", "u1"), ("green", "u1"), ("blue", "u1"), ("intensity", "<f4")])
    scan = np.zeros(n, dtype)
    for name in vertices.dtype.names:
        scan[name] = vertices[name]
    index = np.arange(n)
    scan["red"], scan["green"], scan["blue"] = index & 255, index >> 8 & 255, 200
    scan["intensity"] = index + 0.5
    lines = lines + ["property uchar red", "property uchar green", "property uchar blue", "property float intensity"]
    driver.write_ply(d / "scan.ply", lines, scan, np.zeros((0, 3), "<i4"))
    config = d / "coloured.yaml"
    config.write_text(f"mode: completion\ninputs:\n  scan: {d / 'scan.ply'}\n  template: procedural:vase_template\n"
                      "output:\n  surface: none\nsample:\n  count: 4000\nsynthesize:\n  gap_distance: 1.0\n")
    scanfill("--config", config, "--set", f"output.dir={d / 'single'}", "--threads", 2, "--quiet")
    single = d / "single" / "output.ply"
    scanfill("plan", "--config", config, "--output", d / "c.plan", "--threads", 1, "--quiet")
    scanfill("split", "--config", config, "--tiles", 3, "--output-dir", d / "tiles", "--quiet")
    tiles = sorted((d / "tiles").glob("tile_*.ply"))
    assert "property uchar red" in driver.read_ply(tiles[0])[2]  # the tiles carry the scan's colours
    merged = applied_and_merged(d, d / "c.plan", d / "plan_points.ply", tiles)
    out, _, properties = driver.read_ply(single)
    assert "property float intensity" in properties and "property uchar red" in properties
    assert driver.same_points(merged, single)
    copied = out[out["origin"] == 2]
    assert len(copied) > 0 and (copied["red"] == 128).all() and (copied["intensity"] == 0).all()
    kept = out[out["origin"] != 2]
    assert (kept["blue"] == 200).all()  # the scan's own colours, not by origin


def test_apply_is_byte_identical_at_1_and_2_threads(planned):
    d, _ = planned
    tile = d / "tiles" / "tile_0001.ply"
    for t in (1, 2):
        scanfill("apply", "--plan", d / "vase.plan", "--input", tile, "--output", d / f"t{t}.ply", "--threads", t)
    assert (d / "t1.ply").read_bytes() == (d / "t2.ply").read_bytes()


def refused(args, names, says, output):
    code, err = scanfill(*args, check=False)
    assert code != 0
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert str(names) in lines[0] and says in lines[0], lines[0]
    assert not pathlib.Path(output).exists()


def test_bad_plans_are_refused(planned):
    d, _ = planned
    good = (d / "vase.plan").read_bytes()
    tile, out = d / "tiles" / "tile_0000.ply", d / "bad_out.ply"

    def apply_with(name, content, says):
        plan = d / name
        if content is not None:
            plan.write_bytes(content)
        refused(["apply", "--plan", plan, "--input", tile, "--output", out], plan, says, out)

    apply_with("missing.plan", None, "cannot be opened")
    apply_with("truncated.plan", good[: len(good) // 2], "truncated")
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x01
    apply_with("corrupt.plan", bytes(flipped), "corrupt")
    other = bytearray(good)
    other[8] = 1  # the format version: an older scanfill's plan
    apply_with("v1.plan", bytes(other), "format version 1")
    apply_with("a_tile.plan", tile.read_bytes(), "not a scanfill plan")


def test_bad_tiles_are_refused(planned):
    d, _ = planned
    out = d / "bad_out.ply"
    text = d / "notes.ply"
    text.write_text("these are not points\n")
    refused(["apply", "--plan", d / "vase.plan", "--input", text, "--output", out], text, "", out)
    other = d / "tile.txt"
    other.write_text("1 2 3\n")
    refused(["apply", "--plan", d / "vase.plan", "--input", other, "--output", out], other, "unknown format", out)
    refused(["apply", "--plan", d / "vase.plan", "--input", d / "none.ply", "--output", out], d / "none.ply", "", out)
    # A tile of another scan: the same points moved away.
    far = d / "far.xyz"
    far.write_text("10 10 10\n11 10 10\n10 11 10\n")
    refused(["apply", "--plan", d / "vase.plan", "--input", far, "--output", out], far, "outside the bounds", out)


def test_split_refuses_a_folder_with_tiles_and_plan_refuses_analogy(planned):
    d, _ = planned
    refused(["split", "--config", VASE, *SMALL, "--tiles", 2, "--output-dir", d / "tiles"], d / "tiles",
            "already holds tiles", d / "tiles" / "tile_0004.ply")
    analogy = pathlib.Path(VASE).parent / "analogy_l.yaml"
    refused(["plan", "--config", analogy, "--output", d / "a.plan"], analogy, "analogy", d / "a.plan")
