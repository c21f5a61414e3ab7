"""scanfill plan / split / apply (issue 13 item 3): the tiles' outputs and the plan-level points are the one-process
run's output.ply as a set of points; apply is the same at 1 and 2 threads; bad plans and tiles are refused with one
line naming the file, a non-zero exit and no output."""
import pathlib

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
    other[8] = 2  # the format version
    apply_with("v2.plan", bytes(other), "format version 2")
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
