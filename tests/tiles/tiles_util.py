"""Shared by the tile tests: the scanfill binary, the driver module, and a small vase run."""
import importlib.util
import os
import pathlib
import subprocess

SOURCE = pathlib.Path(os.environ.get("SCANFILL_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = os.environ.get("SCANFILL_BINARY", str(SOURCE / "build" / "scanfill"))
VASE = str(SOURCE / "configs" / "vase.yaml")
# The bundled vase made small (a 160 x 160 scan, 4000 samples: about 6 s); gap_distance 1 makes the template give
# copies, so that the plan-level points are not empty.
SMALL = ["--set", "virtual_scan.width=160", "--set", "virtual_scan.height=160", "--set", "sample.count=4000",
         "--set", "output.surface=none", "--set", "synthesize.gap_distance=1.0"]

_spec = importlib.util.spec_from_file_location("scanfill_dask", SOURCE / "tools" / "scanfill_dask.py")
driver = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(driver)


def scanfill(*args, check=True):
    """Runs scanfill; returns (exit code, stderr)."""
    done = subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True)
    if check:
        assert done.returncode == 0, done.stderr
    return done.returncode, done.stderr


def single_run(out_dir, threads=2, extra=()):
    """The one-process run of the small vase; returns its output.ply."""
    scanfill("--config", VASE, *SMALL, *extra, "--set", f"output.dir={out_dir}", "--threads", threads, "--quiet")
    return pathlib.Path(out_dir) / "output.ply"
