#!/usr/bin/python3
"""Runs scanfill in tiles on a Dask cluster (DESIGN section 10, issue 13).

    scanfill_dask.py run --config C [--set KEY=VALUE ...] --tiles N --work-dir D
                         [--workers N | --scheduler ADDRESS] [--output OUT] [--scanfill BIN]

runs `scanfill plan` once here, `scanfill split` to make the tiles (or takes the tile_*.ply already in
--tiles-dir), submits one `scanfill apply` per tile to the cluster with the plan's path broadcast to every worker,
and merges the tiles' outputs with the plan-level points into one PLY. The work folder must be on storage every
worker sees: a worker reads the plan and its own tile, and writes its tile's output there. Dask does the scheduling;
this script only says what to run.

    scanfill_dask.py merge OUT IN...      merges scanfill's PLY outputs (same vertex properties) into OUT
    scanfill_dask.py compare A B          exit 0 when A and B hold the same points (vertex records) as sets
"""
import argparse
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

_PLY_TYPES = {"uchar": "u1", "char": "i1", "ushort": "<u2", "short": "<i2", "uint": "<u4", "int": "<i4",
              "float": "<f4", "double": "<f8"}


def read_ply(path):
    """The vertex records (a structured array) and faces (F by 3 int32) of a binary little-endian PLY scanfill wrote,
    and the header's vertex property lines."""
    data = pathlib.Path(path).read_bytes()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise ValueError(f"{path}: not a PLY file")
    header = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in header:
        raise ValueError(f"{path}: not a binary little-endian PLY")
    counts, fields, lines, element = {}, [], [], None
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            element = words[1]
            counts[element] = int(words[2])
        elif words[:1] == ["property"] and element == "vertex":
            fields.append((words[2], _PLY_TYPES[words[1]]))
            lines.append(line)
    dtype = np.dtype(fields)
    start = end + len(b"end_header\n")
    vertices = np.frombuffer(data, dtype, counts.get("vertex", 0), start)
    start += vertices.nbytes
    face_dtype = np.dtype([("n", "u1"), ("v", "<i4", 3)])
    faces = np.frombuffer(data, face_dtype, counts.get("face", 0), start)
    if len(faces) and (faces["n"] != 3).any():
        raise ValueError(f"{path}: faces that are not triangles")
    return vertices, faces["v"], lines


def write_ply(path, properties, vertices, faces):
    """Writes vertex records (`properties`: their header lines) and triangles as scanfill does, atomically (a temp
    file renamed into place)."""
    lines = ["ply", "format binary_little_endian 1.0", "comment written by scanfill_dask.py",
             f"element vertex {len(vertices)}", *properties]
    if len(faces):
        lines += [f"element face {len(faces)}", "property list uchar int vertex_indices"]
    lines.append("end_header")
    face_records = np.zeros(len(faces), np.dtype([("n", "u1"), ("v", "<i4", 3)]))
    face_records["n"], face_records["v"] = 3, faces
    path = pathlib.Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix="." + path.name)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # as any file the user makes, not mkstemp's 0600
    try:
        with os.fdopen(fd, "wb") as out:
            out.write(("\n".join(lines) + "\n").encode("ascii"))
            out.write(vertices.tobytes())
            out.write(face_records.tobytes())
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def merge_ply(output, inputs):
    """Concatenates the PLYs' vertices (and triangles, renumbered) in the order given; files without points add
    nothing. All files with points must have the same vertex properties."""
    parts = [(p, *read_ply(p)) for p in inputs]
    parts = [part for part in parts if len(part[1])]
    if not parts:
        raise ValueError("merge: no points in " + ", ".join(map(str, inputs)))
    for path, _, _, properties in parts:
        if properties != parts[0][3]:
            raise ValueError(f"{path}: vertex properties differ from {parts[0][0]}'s")
    offsets = np.cumsum([0] + [len(v) for _, v, _, _ in parts])
    faces = np.concatenate([f + o for (_, _, f, _), o in zip(parts, offsets)])
    write_ply(output, parts[0][3], np.concatenate([v for _, v, _, _ in parts]), faces.astype("<i4"))
    return int(offsets[-1])


def same_points(a, b):
    """Whether two PLYs hold the same vertex records, as multisets (order and triangles aside)."""
    va = read_ply(a)[0]
    vb = read_ply(b)[0]
    if va.dtype != vb.dtype or len(va) != len(vb):
        return False
    record = np.dtype((np.void, va.dtype.itemsize))
    return bool((np.sort(va.view(record)) == np.sort(vb.view(record))).all())


def run_scanfill(scanfill, args):
    """Runs scanfill; raises RuntimeError with its error line when it fails."""
    done = subprocess.run([scanfill, *args], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"scanfill {args[0]} failed ({done.returncode}): {done.stderr.strip()}")
    return done.stdout


def apply_tile(scanfill, plan, tile, output, threads):
    """One task: a worker carries its tile through the plan (both read from shared storage)."""
    run_scanfill(scanfill, ["apply", "--plan", plan, "--input", tile, "--output", output, "--threads", str(threads),
                            "--quiet"])
    return output


def make_client(args):
    from distributed import Client, LocalCluster
    if args.scheduler:
        return Client(args.scheduler)
    cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None)
    return Client(cluster)


def plan_and_tiles(args, work):
    """scanfill plan, then the tiles (made by scanfill split unless --tiles-dir has them)."""
    config = []
    for kv in args.set or []:
        config += ["--set", kv]
    plan, plan_points = work / "scanfill.plan", work / "plan_points.ply"
    run_scanfill(args.scanfill, ["plan", "--config", args.config, *config, "--output", str(plan),
                                 "--plan-points", str(plan_points), "--quiet"])
    tiles_dir = pathlib.Path(args.tiles_dir) if args.tiles_dir else work / "tiles"
    if not args.tiles_dir:
        run_scanfill(args.scanfill, ["split", "--config", args.config, *config, "--tiles", str(args.tiles),
                                     "--output-dir", str(tiles_dir), "--quiet"])
    tiles = sorted(tiles_dir.glob("tile_*.ply"))
    if not tiles:
        raise RuntimeError(f"{tiles_dir}: no tile_*.ply")
    return plan, plan_points, tiles


def run(args):
    work = pathlib.Path(args.work_dir).resolve()
    work.mkdir(parents=True, exist_ok=True)
    if not args.tiles_dir and (work / "tiles").exists():
        shutil.rmtree(work / "tiles")
    times = {}
    t0 = time.monotonic()
    plan, plan_points, tiles = plan_and_tiles(args, work)
    times["plan+split"] = time.monotonic() - t0
    outputs = work / "applied"
    outputs.mkdir(exist_ok=True)
    t1 = time.monotonic()
    with make_client(args) as client:
        shared_plan = client.scatter(str(plan), broadcast=True)  # the one thing every worker shares
        futures = [client.submit(apply_tile, args.scanfill, shared_plan, str(tile), str(outputs / tile.name),
                                 args.task_threads, pure=False) for tile in tiles]
        done = client.gather(futures)
    times["apply"] = time.monotonic() - t1
    t2 = time.monotonic()
    output = pathlib.Path(args.output) if args.output else work / "output.ply"
    points = merge_ply(output, [pathlib.Path(p) for p in done] + [plan_points])
    times["merge"] = time.monotonic() - t2
    print(f"scanfill_dask: {len(tiles)} tiles -> {points} points in {output}; " +
          ", ".join(f"{k} {v:.1f} s" for k, v in times.items()) + f", total {time.monotonic() - t0:.1f} s")
    return 0


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="plan, apply every tile on Dask, merge")
    r.add_argument("--config", required=True)
    r.add_argument("--set", action="append", metavar="KEY=VALUE", help="config override, passed to scanfill")
    r.add_argument("--tiles", type=int, default=8, help="tiles scanfill split makes (default 8)")
    r.add_argument("--tiles-dir", help="use the tile_*.ply here instead of splitting")
    r.add_argument("--work-dir", required=True, help="shared folder: the plan, tiles and their outputs")
    r.add_argument("--output", help="the merged PLY (default WORK_DIR/output.ply)")
    where = r.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786)")
    where.add_argument("--workers", type=int, default=2, help="workers of a LocalCluster (default 2)")
    r.add_argument("--task-threads", type=int, default=1, help="threads of each scanfill apply (default 1)")
    r.add_argument("--scanfill", default=shutil.which("scanfill") or "scanfill", help="the scanfill binary")
    m = sub.add_parser("merge", help="merge PLYs")
    m.add_argument("output")
    m.add_argument("inputs", nargs="+")
    c = sub.add_parser("compare", help="same points as sets?")
    c.add_argument("a")
    c.add_argument("b")
    args = parser.parse_args(argv)
    try:
        if args.command == "merge":
            print(f"{merge_ply(args.output, args.inputs)} points -> {args.output}")
            return 0
        if args.command == "compare":
            same = same_points(args.a, args.b)
            print(f"{args.a} and {args.b}: " + ("the same points" if same else "different points"))
            return 0 if same else 1
        args.scanfill = os.path.abspath(args.scanfill) if os.path.exists(args.scanfill) else args.scanfill
        return run(args)
    except (OSError, ValueError, RuntimeError) as e:
        print(f"scanfill_dask: error: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
