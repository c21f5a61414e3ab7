"""The Dask driver on bench/configs/vase_10m.yaml (issue 13): a LocalCluster of 2 workers over 8 tiles gives the
one-process output as a set of points. Slow (minutes): ctest -L slow."""
import pathlib
import subprocess
import sys
import time

from tiles_util import BINARY, SOURCE, driver, scanfill


def test_dask_driver_on_vase_10m_matches_the_single_process(tmp_path):
    config = SOURCE / "bench" / "configs" / "vase_10m.yaml"
    t0 = time.monotonic()
    scanfill("--config", config, "--set", f"output.dir={tmp_path / 'single'}", "--set", "output.surface=none",
             "--quiet")
    single_s = time.monotonic() - t0
    t1 = time.monotonic()
    done = subprocess.run([sys.executable, str(SOURCE / "tools" / "scanfill_dask.py"), "run", "--config", str(config),
                           "--set", "output.surface=none", "--tiles", "8", "--workers", "2",
                           "--work-dir", str(tmp_path / "work"), "--scanfill", BINARY], capture_output=True, text=True)
    dask_s = time.monotonic() - t1
    assert done.returncode == 0, done.stderr
    print(f"single process {single_s:.1f} s; Dask, 2 workers, 8 tiles {dask_s:.1f} s: {done.stdout.strip()}")
    assert len(list((tmp_path / "work" / "tiles").glob("tile_*.ply"))) == 8
    assert driver.same_points(tmp_path / "work" / "output.ply", pathlib.Path(tmp_path / "single" / "output.ply"))
