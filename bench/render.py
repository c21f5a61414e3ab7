#!/usr/bin/python3
"""Look at outputs: z-buffered point splats of PLY files, seen along --view and from the opposite side, in one PNG.

    python3 bench/render.py OUT.png out/vase/output.ply out/vase/analogy.ply --view=0,-1,0.2 [--size=400]

output.ply is coloured by origin (grey: scan or exemplar, a hue per transform: synthesised, red: copied from the
template); analogy.ply by its own colours. Used to check the robustness sweep's outputs (bench/robustness.py) by eye.
With --reference=REF.ply (the complete model's points, e.g. `scanfill sample --input MODEL --output REF.ply --count
300000`), every file is coloured instead by its distance to the reference: blue within --tau (default 1% of the
reference's diagonal, F-score's threshold), red at 3 tau and beyond; the share within tau per origin is printed.
Needs Debian's python3-numpy and python3-matplotlib (and python3-scipy for --reference; none installed by cmake/dev.sh).
"""
import sys, numpy as np, matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

TYPES = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4", "uint": "u4", "float": "f4",
         "double": "f8", "int8": "i1", "uint8": "u1", "int32": "i4", "uint32": "u4", "float32": "f4", "float64": "f8"}

def read_ply(path):
    f = open(path, "rb")
    props, n, fmt, elem = [], 0, "ascii", None
    while True:
        line = f.readline().decode().strip()
        if line.startswith("format"): fmt = line.split()[1]
        if line.startswith("element"):
            elem = line.split()[1]
            if elem == "vertex": n = int(line.split()[2])
        if line.startswith("property") and elem == "vertex" and "list" not in line:
            _, t, name = line.split(); props.append((name, TYPES[t]))
        if line == "end_header": break
    if fmt == "ascii":
        a = np.loadtxt(f, max_rows=n)
        return {p[0]: a[:, i] for i, p in enumerate(props)}
    end = "<" if fmt == "binary_little_endian" else ">"
    dt = np.dtype([(p, end + t) for p, t in props])
    a = np.frombuffer(f.read(dt.itemsize * n), dtype=dt, count=n)
    return {p: a[p].astype(float) for p, _ in props}

def colours(d):
    n = len(d["x"])
    if "origin" in d:
        c = np.zeros((n, 3)); o = d["origin"]; lab = d.get("label", np.zeros(n))
        c[o == 0] = (0.75, 0.75, 0.75)
        syn = o == 1
        c[syn] = plt.cm.hsv((0.618 * lab[syn] + 0.1) % 1.0)[:, :3]
        c[o == 2] = (0.9, 0.1, 0.1)
        return c
    if "red" in d: return np.stack([d["red"], d["green"], d["blue"]], 1) / 255
    return np.tile((0.6, 0.7, 0.9), (n, 1))

def zbuffer(P, C, N, v, size):
    v = v / np.linalg.norm(v); up = np.array([0, 0, 1.0])
    if abs(v @ up) > 0.95: up = np.array([0, 1.0, 0])
    r = np.cross(up, v); r /= np.linalg.norm(r); u = np.cross(v, r)
    x, y, depth = P @ r, P @ u, P @ v
    lo = np.array([x.min(), y.min()]); span = max(x.max() - x.min(), y.max() - y.min()) * 1.02
    px = ((x - lo[0]) / span * (size - 1)).astype(int); py = ((y - lo[1]) / span * (size - 1)).astype(int)
    shade = C * (0.3 + 0.7 * np.abs(N @ v))[:, None] if N is not None else C
    img = np.ones((size, size, 3)); zb = np.full((size, size), -np.inf)
    rad = 1
    for dx in range(-rad, rad + 1):
        for dy in range(-rad, rad + 1):
            qx = np.clip(px + dx, 0, size - 1); qy = np.clip(py + dy, 0, size - 1)
            order = np.argsort(depth)  # nearest last wins
            idx = qy[order] * size + qx[order]
            zflat = zb.reshape(-1); iflat = img.reshape(-1, 3)
            # keep, per pixel, the last (nearest) point
            last = {}
            uniq, pos = np.unique(idx[::-1], return_index=True)
            src = order[::-1][pos]
            better = depth[src] > zflat[uniq]
            zflat[uniq[better]] = depth[src[better]]; iflat[uniq[better]] = shade[src[better]]
    return img[::-1]

def distance_colours(P, d, ref, tau, name):
    """Blue within tau of the reference, red from 3 tau; prints the share within tau per origin."""
    from scipy.spatial import cKDTree
    dist, _ = cKDTree(ref).query(P)
    origin = d.get("origin", np.zeros(len(P)))
    for o in np.unique(origin):
        m = origin == o
        print(f"{name}: origin {int(o)}: {m.sum()} points, {np.mean(dist[m] <= tau):.3f} within tau {tau:.4g}")
    t = np.clip(dist / tau - 1, 0, 2)[:, None] / 2
    return (1 - t) * np.array([0.1, 0.3, 0.9]) + t * np.array([0.9, 0.1, 0.1])

def main():
    out = sys.argv[1]; view = np.array([0, -1, 0.2]); size = 400; files = []; ref = None; tau = None
    for a in sys.argv[2:]:
        if a.startswith("--view="): view = np.array([float(x) for x in a[7:].split(",")])
        elif a.startswith("--size="): size = int(a[7:])
        elif a.startswith("--reference="):
            r = read_ply(a[12:]); ref = np.stack([r["x"], r["y"], r["z"]], 1)
        elif a.startswith("--tau="): tau = float(a[6:])
        else: files.append(a)
    if not files: sys.exit("render.py: no PLY file to render (usage in the docstring)")
    if ref is not None and tau is None: tau = 0.01 * np.linalg.norm(ref.max(0) - ref.min(0))
    fig, axes = plt.subplots(2, len(files), figsize=(4 * len(files), 8), squeeze=False)
    for j, fn in enumerate(files):
        d = read_ply(fn); P = np.stack([d["x"], d["y"], d["z"]], 1)
        C = colours(d) if ref is None else distance_colours(P, d, ref, tau, fn)
        N = np.stack([d["nx"], d["ny"], d["nz"]], 1) if "nx" in d else None
        for i, v in enumerate([view, -view]):
            ax = axes[i][j]; ax.imshow(np.clip(zbuffer(P, C, N, v, size), 0, 1)); ax.axis("off")
            ax.set_title(f"{'/'.join(fn.split('/')[-3:])} {'view' if i == 0 else 'opposite'}", fontsize=7)
    plt.tight_layout(); plt.savefig(out, dpi=90)

if __name__ == "__main__":
    main()
