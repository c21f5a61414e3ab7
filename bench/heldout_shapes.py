"""Held-out shapes for the robustness sweep: models no test, node or config of scanfill draws, with the templates a
user would draw for them, some at another size than the object (`python3 bench/robustness.py BUILD --held-out`).

    python3 bench/heldout_shapes.py DIR      writes the OBJ files into DIR and prints the cases

- a studded box, 0.6 x 0.6 x 0.9, twelve round studs on each side, plain lid and floor: its plain 8-vertex box at the
  walls, the same box 8% narrower, 10% wider and 5% taller, and 8% shorter standing on the box's floor;
- a golf ball, radius 0.5 with 80 bumps: a plain UV sphere of its radius, 6% larger and 5% smaller;
- a vase with ten grooves twisted about its axis, a bulge and a narrower neck, closed at the bottom: its own body of
  revolution (`revolution:`);
- the sweep's crate (`procedural:crate`, 0.6 x 0.6 x 0.8, raised frames and diamonds on its sides) in a box drawn 8%
  shorter, standing on its floor: a held-out template, not a held-out model.
Pure Python (no numpy), deterministic.
"""
import math
import os
import sys


def write_obj(path, parts):
    """parts: [(vertices, triangles)], triangles indexing their part's vertices from 0."""
    with open(path, "w") as f:
        for vertices, _ in parts:
            for v in vertices:
                f.write("v %.6f %.6f %.6f\n" % tuple(v))
        offset = 0
        for vertices, triangles in parts:
            for t in triangles:
                f.write("f %d %d %d\n" % tuple(i + 1 + offset for i in t))
            offset += len(vertices)


def grid(point, nu, nv):
    """A (nu + 1) x (nv + 1) grid of point(i / nu, j / nv), two triangles per cell."""
    vertices = [point(i / nu, j / nv) for i in range(nu + 1) for j in range(nv + 1)]
    triangles = []
    for i in range(nu):
        for j in range(nv):
            a, b, c, d = i * (nv + 1) + j, (i + 1) * (nv + 1) + j, (i + 1) * (nv + 1) + j + 1, i * (nv + 1) + j + 1
            triangles += [(a, b, c), (a, c, d)]
    return vertices, triangles


def box(size, centre):
    sx, sy, sz = (s / 2 for s in size)
    cx, cy, cz = centre
    v = [(cx + x * sx, cy + y * sy, cz + z * sz) for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)]
    t = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6),
         (1, 3, 5), (3, 7, 5)]
    return [(v, t)]


def studded_box(half=0.3, height=0.9, stud=0.035, n=120):
    def side(origin, u, v, normal, studs):
        def point(s, t):
            h = 0.0
            if studs:
                for a in (0.25, 0.5, 0.75):
                    for b in (0.2, 0.4, 0.6, 0.8):
                        h += stud * math.exp(-(((s - a) * 2 * half) ** 2 + ((t - b) * height) ** 2) / stud ** 2)
            lu, lv = 2 * half, (height if studs else 2 * half)
            return tuple(origin[k] + s * lu * u[k] + t * lv * v[k] + h * normal[k] for k in range(3))
        return grid(point, n, n)
    a = half
    return [side((-a, -a, 0), (1, 0, 0), (0, 0, 1), (0, -1, 0), True),
            side((a, -a, 0), (0, 1, 0), (0, 0, 1), (1, 0, 0), True),
            side((a, a, 0), (-1, 0, 0), (0, 0, 1), (0, 1, 0), True),
            side((-a, a, 0), (0, -1, 0), (0, 0, 1), (-1, 0, 0), True),
            side((-a, -a, height), (1, 0, 0), (0, 1, 0), (0, 0, 1), False),
            side((-a, a, 0), (1, 0, 0), (0, -1, 0), (0, 0, -1), False)]


def sphere(radius_of, nu, nv):
    def point(s, t):
        theta, phi = 2 * math.pi * s, 1e-4 + (math.pi - 2e-4) * t
        d = (math.sin(phi) * math.cos(theta), math.sin(phi) * math.sin(theta), math.cos(phi))
        r = radius_of(d)
        return tuple(r * x for x in d)
    return [grid(point, nu, nv)]


def golf_radius(d, bumps=80, radius=0.5, height=0.03, width=0.09):
    r = radius
    for i in range(bumps):  # a Fibonacci sphere of bump centres
        phi = math.acos(1 - 2 * (i + 0.5) / bumps)
        theta = math.pi * (1 + 5 ** 0.5) * (i + 0.5)
        c = (math.sin(phi) * math.cos(theta), math.sin(phi) * math.sin(theta), math.cos(phi))
        angle = math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(d, c)))))
        if angle < 4 * width:
            r += height * math.exp(-(angle / width) ** 2)
    return r


def twisted_vase(nu=360, nv=160, height=1.2):
    def radius(theta, z):
        return 0.3 + 0.1 * math.sin(math.pi * z / height * 1.5) + 0.025 * math.cos(10 * (theta + 1.2 * z))
    def wall(s, t):
        theta, z = 2 * math.pi * s, height * t
        r = radius(theta, z)
        return (r * math.cos(theta), r * math.sin(theta), z)
    rim = [wall(i / nu, 0) for i in range(nu)]
    bottom = ([(0.0, 0.0, 0.0)] + rim, [(0, (k + 1) % nu + 1, k + 1) for k in range(nu)])
    return [grid(wall, nu, nv), bottom]


def write_heldout(directory):
    """Writes the held-out models and templates into `directory`; returns [(shape, model, [templates])]."""
    os.makedirs(directory, exist_ok=True)
    path = lambda name: os.path.join(directory, name)
    write_obj(path("studded_box.obj"), studded_box())
    write_obj(path("studded_box_template.obj"), box((0.6, 0.6, 0.9), (0, 0, 0.45)))
    write_obj(path("studded_box_narrower.obj"), box((0.552, 0.552, 0.9), (0, 0, 0.45)))
    write_obj(path("studded_box_wider.obj"), box((0.66, 0.66, 0.945), (0, 0, 0.4275)))
    write_obj(path("studded_box_shorter.obj"), box((0.6, 0.6, 0.828), (0, 0, 0.414)))
    write_obj(path("golf_ball.obj"), sphere(golf_radius, 240, 120))
    for name, r in (("golf_ball_template", 0.5), ("golf_ball_larger", 0.53), ("golf_ball_smaller", 0.475)):
        write_obj(path(name + ".obj"), sphere(lambda d, r=r: r, 48, 24))
    write_obj(path("twisted_vase.obj"), twisted_vase())
    write_obj(path("crate_shorter.obj"), box((0.6, 0.6, 0.736), (0, 0, 0.368)))
    return [
        ("held-out: studded box", path("studded_box.obj"),
         [path("studded_box_template.obj"), path("studded_box_narrower.obj"), path("studded_box_wider.obj"),
          path("studded_box_shorter.obj")]),
        ("held-out: golf ball", path("golf_ball.obj"),
         [path("golf_ball_template.obj"), path("golf_ball_larger.obj"), path("golf_ball_smaller.obj")]),
        ("held-out: twisted vase", path("twisted_vase.obj"), ["revolution:" + path("twisted_vase.obj")]),
        ("held-out: crate, its box drawn 8% shorter", "procedural:crate", [path("crate_shorter.obj")]),
    ]


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: heldout_shapes.py DIR")
    for shape, model, templates in write_heldout(sys.argv[1]):
        print(shape, model, *templates)
