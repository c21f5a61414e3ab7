"""The Dask driver (issue 13 item 4) on the small vase: a LocalCluster of 2 workers over 4 tiles gives the
one-process output as a set of points."""
import subprocess
import sys

from tiles_util import BINARY, SMALL, SOURCE, VASE, driver, single_run


def test_dask_driver_matches_the_single_process(tmp_path):
    single = single_run(tmp_path / "single")
    sets = [a for s in SMALL[1::2] for a in ("--set", s)]
    done = subprocess.run([sys.executable, str(SOURCE / "tools" / "scanfill_dask.py"), "run", "--config", VASE, *sets,
                           "--tiles", "4", "--workers", "2", "--work-dir", str(tmp_path / "work"),
                           "--scanfill", BINARY], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "4 tiles" in done.stdout
    assert driver.same_points(tmp_path / "work" / "output.ply", single)
