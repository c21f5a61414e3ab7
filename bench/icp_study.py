#!/usr/bin/env python3
"""Replays correspond's rigid ICP (nodes/correspond/correspond.cpp, rigid_icp) on a run's samples, with variants.

    python3 bench/icp_study.py OUT_DIR [--variant base|normals60|trusted-span] [--tau 0.03] [--classes]

OUT_DIR is a completion run's output folder (samples_scan.ply and samples_template.ply, as every run writes them);
for a transfer, --scan samples_exemplar.ply --template samples_source.ply. Prints the rigid motion found (its angle
and translation). A virtual scan of a procedural model starts at its true pose, so any motion there is drift.

The replay follows the C++: 40 steps, the first third point-to-point on pairs within 3x the median distance, the rest
point-to-plane (the template's normals) with the same trim; pairs whose normals point apart are dropped. It matches
scanfill's own motion to a few tenths of a degree on the gear seen edge-on (9.7 degrees here, scanfill 6.6-9.5).

Variants (stop 33; see README, Robustness sweep):
  base          the C++ before stop 34.
  normals60     also drop point-to-plane pairs whose normals differ by more than 60 degrees.
  trusted-span  solve with every pair as base does, then keep only the part of each point-to-plane step that the
                pairs with normals within 60 degrees constrain: the step is projected onto the eigenvectors of their
                6x6 normal matrix (rotations scaled by the pairs' RMS radius) whose eigenvalue is at least tau times
                the largest, or at least 0.9 of the whole fit's stiffness along it. The C++ since stop 34
                (nodes/core/icp.cpp).
--classes prints, for the first point-to-plane steps, each class of pairs' share of the gradient.
"""
import argparse
import itertools
import sys

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

ITERATIONS, TRIM, AGREE = 40, 3.0, 0.5  # steps, trim (x the median distance), cos 60 degrees
SHARE = 0.9  # trusted-span: a motion only the trusted pairs hold is kept however weak


def read_samples(path):
    """positions and normals of a samples_*.ply (binary little-endian floats: x y z nx ny nz k1 k2 d1x d1y d1z)."""
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().split("\n")
    count = int(next(l for l in header if l.startswith("element vertex")).split()[-1])
    first = next(i for i, l in enumerate(header) if l.startswith("element vertex"))
    vertex = itertools.takewhile(lambda l: not l.startswith(("element", "end_header")), header[first + 1:])
    floats = sum(1 for l in vertex if l.startswith("property float"))  # a scan's camera element follows
    a = np.frombuffer(data[end:end + count * floats * 4], dtype="<f4").reshape(count, floats).astype(float)
    return a[:, :3], a[:, 3:6]


def umeyama_rigid(a, b):
    ca, cb = a.mean(0), b.mean(0)
    u, _, vt = np.linalg.svd((a - ca).T @ (b - cb))
    d = np.diag([1, 1, np.sign(np.linalg.det(vt.T @ u.T))])
    r = vt.T @ d @ u.T
    return r, cb - r @ ca


def point_to_plane(a, b, n, trusted, variant, tau, classes):
    c = a.mean(0)
    p = a - c
    jac = np.hstack([np.cross(p, n), n])
    res = ((a - b) * n).sum(1)
    h = jac.T @ jac
    x = np.linalg.solve(h + np.eye(6) * 1e-6 * np.trace(h) / 6, -jac.T @ res)
    if variant == "trusted-span":
        length = np.sqrt((p ** 2).sum(1).mean())
        scale = np.diag([length] * 3 + [1] * 3)
        jt, ja = jac[trusted] @ np.linalg.inv(scale), jac @ np.linalg.inv(scale)
        ha = ja.T @ ja
        w, v = np.linalg.eigh(jt.T @ jt)
        whole = np.einsum("ik,ij,jk->k", v, ha, v) + 1e-9 * np.trace(ha) + 1e-300
        kept = v[:, (w >= tau * w.max()) | (w >= SHARE * whole)]
        x = np.linalg.solve(scale, kept @ (kept.T @ (scale @ x)))
    if classes:
        for name, m in [("normals agree", trusted), ("normals differ > 60 deg", ~trusted)]:
            g = -(jac[m].T @ res[m])
            print(f"   {name:24s} pairs {m.sum():6d}  gradient: rotation {np.round(g[:3], 4)} "
                  f"translation {np.round(g[3:], 4)}")
    r = Rotation.from_rotvec(x[:3]).as_matrix()
    return r, c + x[3:] - r @ c


def replay(scan, scan_n, templ, templ_n, variant, tau, classes):
    tree = cKDTree(templ)
    rot, tr = np.eye(3), np.zeros(3)
    coarse = ITERATIONS // 3
    for it in range(ITERATIONS):
        moved, normals = scan @ rot.T + tr, scan_n @ rot.T
        dist, j = tree.query(moved)
        cosn = (normals * templ_n[j]).sum(1)
        keep = (dist ** 2 <= TRIM * TRIM * np.median(dist ** 2)) & (cosn >= 0)
        if it >= coarse and variant == "normals60":
            keep &= cosn >= AGREE
        a, b, n = moved[keep], templ[j[keep]], templ_n[j[keep]]
        if it < coarse:
            r, t = umeyama_rigid(a, b)
        else:
            r, t = point_to_plane(a, b, n, cosn[keep] >= AGREE, variant, tau, classes and it < coarse + 2)
        rot, tr = r @ rot, r @ tr + t
    return rot, tr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("--scan", default="samples_scan.ply")
    ap.add_argument("--template", default="samples_template.ply")
    ap.add_argument("--variant", default="base", choices=["base", "normals60", "trusted-span"])
    ap.add_argument("--tau", type=float, default=0.03)
    ap.add_argument("--classes", action="store_true")
    args = ap.parse_args()
    try:
        scan, scan_n = read_samples(f"{args.out_dir}/{args.scan}")
        templ, templ_n = read_samples(f"{args.out_dir}/{args.template}")
    except (OSError, ValueError, StopIteration) as e:
        sys.exit(f"icp_study: cannot read the samples in {args.out_dir}: {e}")
    rot, tr = replay(scan, scan_n, templ, templ_n, args.variant, args.tau, args.classes)
    angle = np.degrees(np.arccos(np.clip((np.trace(rot) - 1) / 2, -1, 1)))
    print(f"{args.variant}: angle {angle:.2f} deg, translation {np.round(tr, 4)} (norm {np.linalg.norm(tr):.4f})")


if __name__ == "__main__":
    main()
