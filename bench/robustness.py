#!/usr/bin/env python3
"""Robustness sweep (issue 10): shapes x viewpoints x template kinds, each scored against the complete model.

Every completion case is a virtual single-view range scan (`scanfill scan`) of a complete model, completed with a
template, and scored by `scanfill eval --scan --template --baselines` against the complete model: F-score at 1% of the
diagonal and unseen-detail recall, beside the two baselines (the scan alone, template blending). Transfer cases are
scored against the styled target. Prints one JSON line per run and, at the end, a Markdown table per shape (min and
median of F and unseen-detail, and the baselines' medians).

    python3 bench/robustness.py build [--out DIR] [--only SUBSTRING,...] [--threads N] [--json FILE] [--preset NAME]
                                      [--set KEY=VALUE]... [--check-floors] [--random-views N [--view-seed S]]
                                      [--end-on] [--noise SHARE] [--resolution N] [--held-out]

--end-on replaces the six views by two nearly along the up axis (AXIS_VIEWS, 2 degrees off it): a scan of the top or
the bottom only, as of an object lying on a table, where a column or a crate shows little of its style; with
--check-floors it names where the issue's floors fall short there (they are not expected to hold end on).
--noise gives the virtual scans range noise (Gaussian along each ray, seeded) of SHARE times the model's diagonal, as a
real scanner's: 0.003 is about a third of the F-score's threshold.
--resolution sets the virtual scanner's image (N by N rays; 480 by default): 160 gives a sparse scan of some 6000
points, sparser than the template's samples, whose points are then used as they are (unevenly dense).
--held-out runs only the shapes of bench/heldout_shapes.py instead (a studded box, a golf ball, a twisted vase; no test
or node of scanfill draws them), with the plain templates a user would draw, at their models' size and off it, and the
sweep's crate in a box drawn 8% shorter.
With --check-floors it runs only the shapes that have floors (FLOORS, REGRESSION_MEANS below) and exits 1, naming
each shortfall, when a run fails or a shape is below them. CTest runs it so as `robustness.sweep_floors` (label slow).

Needs ../shared/data for the real cases (skipped with a message when absent).
"""
import argparse
import json
import math
import os
import random
import statistics
import subprocess
import sys
import time

import heldout_shapes

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(os.path.dirname(ROOT), "shared", "data")

# Eye directions (normalised below): four around, one from above, one from below.
VIEWS = {
    "front": (0.0, -1.0, 0.2),
    "side": (1.0, 0.0, 0.25),
    "back_oblique": (-0.7, 0.7, 0.5),
    "front_oblique": (0.6, -0.8, 0.4),
    "above": (0.25, -0.35, 1.0),
    "below": (0.35, -0.25, -1.0),
}

# --end-on: straight from above and from below, 2 degrees off the up axis (exactly on it, the scanner's image has no up).
AXIS_VIEWS = {
    "straight_above": (0.03, 0.02, 1.0),
    "straight_below": (0.03, 0.02, -1.0),
}

# (shape, model, [templates])
COMPLETIONS = [
    ("vase", "procedural:vase", ["procedural:vase_template", "revolution:procedural:vase"]),
    ("fluted column", "procedural:column",
     ["procedural:column_template", "procedural:column_template24", "procedural:column_template8",
      "procedural:column_template6"]),
    ("gear", "procedural:gear", ["procedural:gear_template"]),
    ("table", "procedural:table", ["procedural:table_template"]),
    ("crate (box template)", "procedural:crate", ["procedural:crate_template"]),
    ("beaded ring (torus template)", "procedural:beaded_ring", ["procedural:ring_template"]),
    ("triangular prism (6-vertex template)", "procedural:medallion_prism", ["procedural:prism_template"]),
    ("hexagonal prism (12-vertex template)", "procedural:medallion_prism6", ["procedural:prism_template6"]),
]

# Procedural shapes found on inputs no test chose, in the sweep without the issue's floors until every view meets them
# (README, "Seen at stop 41"): a box that is not square, its short sides reached by turns between its faces; the vase
# in a plain cylinder (stop 45), whose copied caps and foot lie off the vase; a barrel with a medallion at each quarter
# turn, completed with its own body of revolution (stop 49), whose medallions only quarter turns carry to its back. The
# fluted column's octagon (vertices on its radius) was here from stop 57, where ICP pulled a scan seen square on a
# corner into it, until stop 58 registered round scans on the body through its corners. The vase's hexagon (stop 59)
# stands with its plain cylinder: its body's copied caps lie over the vase's open ends. The cup (stop 74) is the vase as a
# vessel, whose inside a view from above sees through its mouth: the vase is one open sheet, and the virtual scanner keeps
# only the faces turned to it, so the vase's inside (the backs of its faces) is never seen.
BEYOND_FLOORS = [
    ("ribbed box, not square (box template)", "procedural:ribbed_box", ["procedural:ribbed_box_template"]),
    ("vase (plain cylinder template)", "procedural:vase", ["procedural:vase_cylinder", "procedural:vase_cylinder6"]),
    ("cup: the vase with a wall and a floor (plain cylinder and body templates)", "procedural:cup",
     ["procedural:vase_cylinder", "procedural:vase_template"]),
    ("medallion barrel (revolution: template)", "procedural:medallion_barrel",
     ["revolution:procedural:medallion_barrel"]),
]

# Real models drawn y-up, as many meshes are (shape, file under ../shared/data/models, template kind): completed with
# their own body of revolution or bounding box, from the same views turned to y-up.
REAL_Y_UP = [
    ("real y-up: vase (text2mesh)", "text2mesh_vase.obj", "revolution:"),
    ("real y-up: candle (text2mesh)", "text2mesh_candle.obj", "revolution:"),
    ("real y-up: square pillar (3D scan, box template)", "threedscans_Column03.obj", "box:"),
    ("real y-up: teapot", "teapot.obj", "revolution:"),
]

# Real round models in the plain closed cylinder a user might draw about them (stop 73): 24 sides, the model's
# bounding-box height about its up axis, its radius the mean of the box's half-widths across it (cylinder_of). Not the
# object's profile: a vase's neck and belly lie well inside or outside it. (shape, file under ../shared/data/models, up)
ROUND_IN_CYLINDER = [
    ("real: Vase-Lion, a plain 24-sided cylinder", "vaselion.obj", "z"),
    ("real y-up: vase (text2mesh), a plain 24-sided cylinder", "text2mesh_vase.obj", "y"),
    ("real y-up: candle (text2mesh), a plain 24-sided cylinder", "text2mesh_candle.obj", "y"),
]

# A user with only the scan: its own body of revolution as template (`revolution:` of the scan file; SCAN stands for
# it). (shape, model, up): the model under ../shared/data/models unless procedural. The procedural vase has a
# regression floor (REGRESSION_MEANS); from below its scan sees too little height for the issue's floors.
OWN_SCAN = [
    ("vase, revolution: of its scan", "procedural:vase", "z"),
    ("real: Vase-Lion, revolution: of its scan", "vaselion.obj", "z"),
    ("real y-up: vase (text2mesh), revolution: of its scan", "text2mesh_vase.obj", "y"),
    ("real y-up: candle (text2mesh), revolution: of its scan", "text2mesh_candle.obj", "y"),
]

# Issue 10's floors, per shape: on the procedural shapes (completions and two-body transfers) F@1% >= 0.95 on every
# run, unseen-detail median >= 0.85 and minimum >= 0.6, and every run above template blending on both numbers. The
# Vase-Lion has a regression floor on its means (the issue asks 0.8 / 0.5; measured 0.676 / 0.416 at stop 30).
FLOORS = {"f_min": 0.95, "unseen_median": 0.85, "unseen_min": 0.6}
REGRESSION_MEANS = {"real: Vase-Lion": {"f": 0.65, "unseen": 0.38},
                    # the vase's own scan revolved (stop 37: means 0.967 / 0.597; 0.813 / 0.336 before it)
                    "vase, revolution: of its scan": {"f": 0.93, "unseen": 0.5}}

# (shape, source, target, exemplar, styled target)
TRANSFERS = [
    ("two disks, equal", "procedural:gear_template", "procedural:disk_pair", "procedural:gear", "procedural:gear_pair"),
    ("two disks, second 0.7", "procedural:gear_template", "procedural:disk_pair_scaled", "procedural:gear",
     "procedural:gear_pair_scaled"),
]


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        raise RuntimeError(" ".join(cmd) + "\n" + r.stderr.strip())
    return r.stdout


def bbox_of(exe, shape, work):
    """Bounding box of a model: `scanfill info --full` (every point read) for files, a sampled copy for procedural
    shapes."""
    if shape.startswith("procedural:"):
        path = os.path.join(work, shape.split(":", 1)[1] + "_bbox.ply")
        if not os.path.exists(path):
            run([exe, "sample", "--input", shape, "--output", path, "--count", "2000"])
        shape = path
    return json.loads(run([exe, "info", "--full", "--json", shape]))["bbox"]


def eye_for(bbox, view, up="z"):
    """The eye for a view of a model whose up axis is `up` (z, or y for models drawn y-up)."""
    lo, hi = bbox
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    diag = math.dist(lo, hi)
    d = VIEWS[view]
    if up == "y":
        d = (d[0], d[2], -d[1])
    n = math.sqrt(sum(x * x for x in d))
    return centre, [c + 2.6 * diag * x / n for c, x in zip(centre, d)]


def cylinder_of(exe, model, up, work):
    """ROUND_IN_CYLINDER's template for `model` (an OBJ under `work`): a closed 24-sided cylinder about its up axis
    (z or y), its faces wound outwards."""
    lo, hi = bbox_of(exe, model, work)
    axis, across = (2, (0, 1)) if up == "z" else (1, (2, 0))  # across[0] x across[1] = the up axis
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    r = sum(hi[k] - lo[k] for k in across) / 4
    verts = []
    for i in range(24):
        for end in (lo[axis], hi[axis]):
            p = list(centre)
            p[across[0]] += r * math.cos(2 * math.pi * i / 24)
            p[across[1]] += r * math.sin(2 * math.pi * i / 24)
            p[axis] = end
            verts.append(p)
    for end in (lo[axis], hi[axis]):
        verts.append([end if k == axis else centre[k] for k in range(3)])
    faces = []
    for i in range(24):
        i0, i1, j0, j1 = 2 * i + 1, 2 * i + 2, 2 * ((i + 1) % 24) + 1, 2 * ((i + 1) % 24) + 2
        faces += [(i0, j0, j1), (i0, j1, i1), (49, j0, i0), (50, i1, j1)]
    path = os.path.join(work, os.path.splitext(os.path.basename(model))[0] + "_cylinder24.obj")
    with open(path, "w") as f:
        f.writelines(f"v {p[0]:.6f} {p[1]:.6f} {p[2]:.6f}\n" for p in verts)
        f.writelines(f"f {a} {b} {c}\n" for a, b, c in faces)
    return path


def yaml_list(v):
    return "[" + ", ".join(f"{x:.6g}" for x in v) + "]"


def completion_case(exe, work, shape, model, template, view, preset, up="z", noise=0.0, resolution=480):
    name = f"{shape} | {template.split(':')[-1]} | {view}"
    tag = "".join(c if c.isalnum() else "_" for c in name)
    d = os.path.join(work, tag)
    os.makedirs(d, exist_ok=True)
    bbox = bbox_of(exe, model, work)
    centre, eye = eye_for(bbox, view, up)
    scan = os.path.join(d, "scan.ply")
    sensor = ["--noise", f"{noise * math.dist(*bbox):.9g}", "--seed", "1"] if noise > 0 else []
    run([exe, "scan", "--input", model, "--output", scan, "--eye", ",".join(map(str, eye)), "--target",
         ",".join(map(str, centre)), "--resolution", f"{resolution},{resolution}", "--fov", "30"] + sensor)
    if template == "revolution:SCAN":
        template = "revolution:" + scan
    if template == "CYLINDER":
        template = cylinder_of(exe, model, up, work)
    cfg = os.path.join(d, "config.yaml")
    with open(cfg, "w") as f:
        f.write(f"mode: completion\ninputs:\n  scan: {scan}\n  template: {template}\noutput:\n  dir: {d}/out\n"
                f"sample:\n  count: 20000\npreset: {preset}\n")
    return name, cfg, os.path.join(d, "out"), ["--reference", model, "--scan", scan, "--template", template,
                                              "--baselines"]


def transfer_case(work, shape, source, target, exemplar, preset):
    tag = "".join(c if c.isalnum() else "_" for c in shape)
    d = os.path.join(work, tag)
    os.makedirs(d, exist_ok=True)
    cfg = os.path.join(d, "config.yaml")
    with open(cfg, "w") as f:
        f.write(f"mode: transfer\ninputs:\n  source: {source}\n  target: {target}\n  exemplar: {exemplar}\n"
                f"output:\n  dir: {d}/out\nsample:\n  count: 20000\npreset: {preset}\n")
    return cfg, os.path.join(d, "out")


def score(exe, out_dir, eval_args, threads):
    j = json.loads(run([exe, "eval", "--output", os.path.join(out_dir, "output.ply"), "--threads", str(threads)] +
                       eval_args))
    report = json.load(open(os.path.join(out_dir, "report.json")))
    o = report.get("output", {})
    used = [t for t in report["transforms"] if t["kind"] == "similarity" and t["labelled"] > 0]
    row = {"f": j["fscore"], "unseen": j.get("unseen_detail_recall"),
           "copied_points": o.get("copied_points"), "output_points": o.get("points"),
           "labels_used": len(used), "axis_rotations_used": sum(1 for t in used if t.get("axis_rotation")),
           "transforms": len(report["transforms"]) - 1}
    for b, v in j.get("baselines", {}).items():
        row[b + "_f"] = v["fscore"]
        row[b + "_unseen"] = v["unseen_detail_recall"]
    return row


def procedural_shapes():
    return [c[0] for c in COMPLETIONS] + [t[0] for t in TRANSFERS]


def shortfalls_of_procedural(shape, rs):
    out = []
    for r in rs:
        if r["f"] < FLOORS["f_min"]:
            out.append(f"{r['case']}: F {r['f']:.3f} < {FLOORS['f_min']}")
        for k in ("f", "unseen"):
            blend = r.get("template_blend_" + k)
            if blend is not None and not (r[k] or 0) > blend:
                out.append(f"{r['case']}: {k} {r[k] or 0:.3f} not above template blending's {blend:.3f}")
    unseen = [r["unseen"] or 0 for r in rs]
    if statistics.median(unseen) < FLOORS["unseen_median"]:
        out.append(f"{shape}: median unseen-detail {statistics.median(unseen):.3f} < {FLOORS['unseen_median']}")
    if min(unseen) < FLOORS["unseen_min"]:
        out.append(f"{shape}: min unseen-detail {min(unseen):.3f} < {FLOORS['unseen_min']}")
    return out


def shortfalls_of_means(shape, rs, floors):
    out = []
    for k, floor in floors.items():
        mean = statistics.mean(r[k] or 0 for r in rs)
        if mean < floor:
            out.append(f"{shape}: mean {k} {mean:.3f} < regression floor {floor}")
    return out


def floor_shortfalls(rows):
    """Every run that failed, and every shape of the sweep below its floors (FLOORS, REGRESSION_MEANS)."""
    out = [f"{r['case']}: failed: {r['error']}" for r in rows if "error" in r]
    for shape in dict.fromkeys(r["shape"] for r in rows):
        rs = [r for r in rows if r["shape"] == shape and "error" not in r]
        if not rs:
            continue
        if shape in procedural_shapes():
            out += shortfalls_of_procedural(shape, rs)
        elif shape in REGRESSION_MEANS:
            out += shortfalls_of_means(shape, rs, REGRESSION_MEANS[shape])
    return out


def random_views(n, seed):
    """n eye directions drawn uniformly on the sphere (rejection from the cube), named by their coordinates."""
    rng = random.Random(seed)
    views = {}
    while len(views) < n:
        v = [rng.uniform(-1, 1) for _ in range(3)]
        norm = math.sqrt(sum(x * x for x in v))
        if 0.3 < norm <= 1:
            views[f"r{len(views)}_" + "_".join(f"{x / norm:+.2f}" for x in v)] = tuple(x / norm for x in v)
    return views


def real_and_transfer_cases():
    """The sweep's real completions (drawn z-up and y-up), its own-scan templates and its transfers, as main's cases."""
    cases = []
    vaselion = os.path.join(DATA, "models", "vaselion.obj")
    if os.path.exists(vaselion):
        for view in VIEWS:
            cases.append(("completion", "real: Vase-Lion", vaselion, "revolution:" + vaselion, view, "z"))
        for shape, file, kind in REAL_Y_UP:
            model = os.path.join(DATA, "models", file)
            for view in VIEWS:
                cases.append(("completion", shape, model, kind + model, view, "y"))
        for shape, file, up in ROUND_IN_CYLINDER:
            for view in VIEWS:
                cases.append(("completion", shape, os.path.join(DATA, "models", file), "CYLINDER", view, up))
    for shape, file, up in OWN_SCAN:
        model = file if file.startswith("procedural:") else os.path.join(DATA, "models", file)
        if os.path.exists(model) or file.startswith("procedural:"):
            for view in VIEWS:
                cases.append(("completion", shape, model, "revolution:SCAN", view, up))
    if not os.path.exists(vaselion):
        print(f"skipping the real cases: {vaselion} is absent", file=sys.stderr)
    for t in TRANSFERS:
        cases.append(("transfer",) + t)
    return cases


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build")
    ap.add_argument("--out", default="/tmp/scanfill_robustness")
    ap.add_argument("--only", default="", help="run only cases whose name contains this (several: comma-separated)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--json", default="", help="also write all rows to this file")
    ap.add_argument("--preset", default="scanfill", help="the config's preset key (scanfill or paper)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="override a config key in every run (scanfill --set), repeatable")
    ap.add_argument("--check-floors", action="store_true", help="exit 1 when a shape is below its floors (FLOORS)")
    ap.add_argument("--run-binary", default="", help="another scanfill for the main run (e.g. an older build to compare)")
    ap.add_argument("--random-views", type=int, default=0, metavar="N",
                    help="N seeded random eye directions instead of the six named views (views no test chose)")
    ap.add_argument("--view-seed", type=int, default=2026, help="seed of --random-views")
    ap.add_argument("--end-on", action="store_true",
                    help="two views nearly along the up axis (AXIS_VIEWS) instead of the six named views")
    ap.add_argument("--noise", type=float, default=0.0, metavar="SHARE",
                    help="range noise of the virtual scans (sigma along the ray) as a share of the model's diagonal")
    ap.add_argument("--resolution", type=int, default=480, metavar="N",
                    help="the virtual scanner's image, N by N rays (a sparse scan: 160)")
    ap.add_argument("--held-out", action="store_true",
                    help="only the held-out shapes of bench/heldout_shapes.py (written under --out), with templates "
                         "at and off their models' size")
    args = ap.parse_args()
    if args.end_on and args.random_views > 0:
        ap.error("--end-on and --random-views each replace the named views: give one of them")
    if args.end_on:
        VIEWS.clear()
        VIEWS.update(AXIS_VIEWS)
    if args.random_views > 0:
        VIEWS.clear()
        VIEWS.update(random_views(args.random_views, args.view_seed))
    exe = os.path.join(os.path.abspath(args.build), "scanfill")
    os.makedirs(args.out, exist_ok=True)
    cases = []  # (shape, name, cfg, out_dir, eval args)
    completions = COMPLETIONS + BEYOND_FLOORS
    if args.held_out:
        if args.check_floors:
            ap.error("--held-out shapes have no floors: leave out --check-floors")
        completions = heldout_shapes.write_heldout(os.path.join(args.out, "held-out models"))
    for shape, model, templates in completions:
        for template in templates:
            for view in VIEWS:
                cases.append(("completion", shape, model, template, view, "z"))
    if not args.held_out:
        cases += real_and_transfer_cases()
    rows = []
    t_all = time.time()
    for case in cases:
        label = " | ".join(str(x) for x in case[1:-1 if case[0] == "completion" else None]
                           if not str(x).startswith("/"))
        if args.only and not any(o in label for o in args.only.split(",")):
            continue
        if args.check_floors and case[1] not in procedural_shapes() and case[1] not in REGRESSION_MEANS:
            continue
        t0 = time.time()
        try:
            if case[0] == "completion":
                _, shape, model, template, view, up = case
                name, cfg, out_dir, eval_args = completion_case(exe, args.out, shape, model, template, view,
                                                                args.preset, up, args.noise, args.resolution)
            else:
                _, shape, source, target, exemplar, styled = case
                name = shape
                cfg, out_dir = transfer_case(args.out, shape, source, target, exemplar, args.preset)
                eval_args = ["--reference", styled, "--scan", exemplar, "--template", target, "--baselines"]
            overrides = [x for kv in args.set for x in ("--set", kv)]
            run([args.run_binary or exe, "--config", cfg, "--threads", str(args.threads), "-q"] + overrides)
            row = {"shape": shape, "case": name, **score(exe, out_dir, eval_args, args.threads)}
        except RuntimeError as e:
            row = {"shape": case[1], "case": label, "error": str(e).splitlines()[-1]}
        row["seconds"] = round(time.time() - t0, 1)
        rows.append(row)
        print(json.dumps(row), flush=True)
    if args.json:
        json.dump(rows, open(args.json, "w"), indent=1)
    print(f"\n{len(rows)} runs in {time.time() - t_all:.0f} s\n")
    print("| shape | runs | F min / median | unseen-detail min / median | scan only F / unseen (median) | "
          "template blend F / unseen (median) |")
    print("|---|---|---|---|---|---|")
    for shape in dict.fromkeys(r["shape"] for r in rows):
        rs = [r for r in rows if r["shape"] == shape and "error" not in r]
        errors = sum(1 for r in rows if r["shape"] == shape and "error" in r)
        if not rs:
            print(f"| {shape} | {errors} failed | | | | |")
            continue
        med = lambda k: statistics.median(r[k] or 0 for r in rs)
        mn = lambda k: min(r[k] or 0 for r in rs)
        print(f"| {shape} | {len(rs)}{f' (+{errors} failed)' if errors else ''} | {mn('f'):.3f} / {med('f'):.3f} | "
              f"{mn('unseen'):.2f} / {med('unseen'):.2f} | {med('scan_only_f'):.3f} / {med('scan_only_unseen'):.2f} | "
              f"{med('template_blend_f'):.3f} / {med('template_blend_unseen'):.2f} |")
    if args.check_floors:
        shortfalls = floor_shortfalls(rows)
        for s in shortfalls:
            print("below the floor: " + s, file=sys.stderr)
        if shortfalls:
            sys.exit(1)
        print(f"every shape meets its floors ({len(rows)} runs)")


if __name__ == "__main__":
    main()
