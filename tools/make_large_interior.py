#!/usr/bin/env python3
"""Generates a large interior, tessellated the way a Blender export is, for the scaling work on
scenes of a quarter million triangles (docs/performance.md, "Large interior"). Not committed:
written into the build tree or a temporary folder.

A hall 12 m wide (x in [-6, 6]), 24 m long (z in [-12, 12]), y up: a nave under a barrel vault
(radius 3.2 m, springing at y = 8) between two arcades of 8 columns each (cylinders, with a base
and a capital), 7 semicircular arches a row, and an aisle on each side under a flat ceiling at
y = 8. The floor is 0.5 m tiles (0.49 m quads, a 1 cm grout gap) in two alternating stones over a
grout sheet 5 mm below. Light comes in through four windows in the wall at x = 6 (an emissive
sky panel 1 m outside each) and a skylight in the vault's crown (an emissive panel above it);
red curtains (wavy sheets) hang beside each window; four pendant lamps (a cord, a conical shade
and an emissive disc) hang in the nave; four KHR_lights_punctual point lights (sconces) light
the wall at x = -6; one perspective camera stands at the south end looking up the hall.

Everything is triangles in indexed meshes, one node per object; the columns, arches, curtains,
rods and lamps are linked duplicates (one mesh, a node each) as Blender exports them; every
material is doubleSided with metallicFactor 0 (Blender's defaults, Principled BSDF), emission
as emissiveFactor times KHR_materials_emissive_strength (nits). Reflectances are under 0.8.
Flat parts are grids of about `density` cells a metre, curved parts twice as fine around; the
density is searched, and the grout sheet's grid sized, so that the triangle count (every
instance counted) is within 0.1% of --triangles from 5,000 up (search() below). Deterministic:
the same arguments give the same bytes. Units: metres.

Usage: make_large_interior.py [--triangles N] -o PATH(.gltf|.glb)
   (.gltf: PATH and PATH's name with .bin beside it; default 250000 triangles)
"""
import argparse
import math
import sys

from gltf_writer import GltfBuilder, write_binary

HALF_W, HALF_D = 6.0, 12.0  # hall: x in [-6, 6], z in [-12, 12]
AISLE_H = 8.0  # aisle ceilings and the vault's springing
ARCADE_X, ARCADE_T = 3.5, 0.6  # arcade centre lines x = +-3.5, wall thickness
VAULT_R = ARCADE_X - ARCADE_T / 2  # the vault springs from the arcades' nave faces
COLUMN_Z = [-10.5 + 3.0 * k for k in range(8)]
COLUMN_R, BASE_H, CAPITAL_H, SPRING_Y = 0.3, 0.3, 0.3, 5.0
BASE_HALF, CAPITAL_HALF = 0.4, 0.45
ARCH_R = 1.05  # clear span 2.1 m: the arch springs from the capitals
WINDOW_Z = [-9.0, -3.0, 3.0, 9.0]
WINDOW_HALF_W, WINDOW_Y0, WINDOW_Y1 = 0.8, 1.5, 5.5
SKYLIGHT_HALF_X, SKYLIGHT_HALF_Z = 1.0, 4.0
LAMP_Z = [-7.5, -2.5, 2.5, 7.5]
LAMP_Y = 4.5  # the shade's rim
SCONCE_Z = [-9.0, -3.0, 3.0, 9.0]
TILE, GROUT = 0.5, 0.01


def material(name, rgb, emission=None, strength=None):
    m = {"name": name, "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": list(rgb) + [1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": 0.5}}
    if emission:
        m["emissiveFactor"] = list(emission)
        m["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}
    return m


MATERIALS = [
    material("plaster", (0.72, 0.68, 0.6)),
    material("ceiling", (0.78, 0.77, 0.74)),
    material("stone", (0.55, 0.52, 0.46)),
    material("tile_light", (0.7, 0.67, 0.6)),
    material("tile_dark", (0.22, 0.2, 0.19)),
    material("grout", (0.4, 0.39, 0.37)),
    material("curtain", (0.55, 0.1, 0.08)),
    material("brass", (0.45, 0.35, 0.15)),
    material("cord", (0.05, 0.05, 0.05)),
    material("bulb", (0.8, 0.8, 0.8), (1.0, 0.8, 0.55), 20.0),
    material("sky", (0.0, 0.0, 0.0), (0.75, 0.85, 1.0), 8.0),
    material("sun_sky", (0.0, 0.0, 0.0), (1.0, 0.95, 0.85), 16.0),
]
MAT = {m["name"]: k for k, m in enumerate(MATERIALS)}


class Part:
    """Indexed triangles of one material: positions (x, y, z) and triangle index triples."""

    def __init__(self):
        self.positions, self.triangles = [], []

    def grid(self, point, n_u, n_v, skip=None):
        """A (n_u x n_v)-cell grid of point(i / n_u, j / n_v), each cell two triangles (the
        cell (i, j) left out where skip(i, j)), wound counter-clockwise in (u, v)."""
        base = len(self.positions)
        self.positions += [point(i / n_u, j / n_v) for j in range(n_v + 1) for i in range(n_u + 1)]
        row = n_u + 1
        for j in range(n_v):
            for i in range(n_u):
                if skip and skip(i, j):
                    continue
                a = base + j * row + i
                self.triangles += [(a, a + 1, a + row + 1), (a, a + row + 1, a + row)]

    def fan(self, centre, rim, n_rings, closed):
        """A disc (closed: the rim points go all round) or a sector (the rim from its first
        point to its last) around `centre`, in n_rings rings: triangles at the centre, quads
        (two triangles) outside."""
        base = len(self.positions)
        self.positions.append(centre)
        for r in range(1, n_rings + 1):
            f = r / n_rings
            self.positions += [tuple(c + f * (q - c) for c, q in zip(centre, p)) for p in rim]
        n = len(rim)
        ring = lambda r, k: base + 1 + (r - 1) * n + k % n  # noqa: E731
        for k in range(n if closed else n - 1):
            self.triangles.append((base, ring(1, k), ring(1, k + 1)))
            for r in range(1, n_rings):
                a, b = ring(r, k), ring(r, k + 1)
                c, d = ring(r + 1, k + 1), ring(r + 1, k)
                self.triangles += [(a, d, c), (a, c, b)]

    def indices(self):
        return [i for t in self.triangles for i in t]


def cells(length, density, least=1):
    return max(least, math.ceil(length * density - 1e-9))


def lerp(a, b, t):
    return a + (b - a) * t


def subdivide(breaks, density, scale=1.0):
    """The points cutting each interval between `breaks` into cells at `density` (lengths times
    `scale`), the last break included, and each cell's interval index."""
    points, interval = [], []
    for a, (u0, u1) in enumerate(zip(breaks, breaks[1:])):
        n = cells((u1 - u0) * scale, density)
        points += [lerp(u0, u1, k / n) for k in range(n)]
        interval += [a] * n
    return points + [breaks[-1]], interval


def breaks_grid(part, point, u_breaks, v_breaks, density, holes=(), u_scale=1.0):
    """A grid over the intervals between u_breaks and v_breaks, each interval cut into cells at
    `density` (u lengths times u_scale); point(u, v) places it; the intervals (a, b) in `holes`
    are left out."""
    us, iu = subdivide(u_breaks, density, u_scale)
    vs, iv = subdivide(v_breaks, density)
    part.grid(lambda s, t: point(us[round(s * (len(us) - 1))], vs[round(t * (len(vs) - 1))]),
              len(us) - 1, len(vs) - 1, skip=lambda i, j: (iu[i], iv[j]) in holes)


def box(part, lo, hi, density, faces="xXyYzZ"):
    """The faces of an axis-aligned box (x/X: the -x/+x face, ...), outward."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    n = lambda length: cells(length, density)  # noqa: E731
    if "x" in faces:
        part.grid(lambda u, v: (x0, lerp(y0, y1, v), lerp(z0, z1, u)), n(z1 - z0), n(y1 - y0))
    if "X" in faces:
        part.grid(lambda u, v: (x1, lerp(y0, y1, u), lerp(z0, z1, v)), n(y1 - y0), n(z1 - z0))
    if "y" in faces:
        part.grid(lambda u, v: (lerp(x0, x1, u), y0, lerp(z0, z1, v)), n(x1 - x0), n(z1 - z0))
    if "Y" in faces:
        part.grid(lambda u, v: (lerp(x0, x1, v), y1, lerp(z0, z1, u)), n(z1 - z0), n(x1 - x0))
    if "z" in faces:
        part.grid(lambda u, v: (lerp(x0, x1, v), lerp(y0, y1, u), z0), n(y1 - y0), n(x1 - x0))
    if "Z" in faces:
        part.grid(lambda u, v: (lerp(x0, x1, u), lerp(y0, y1, v), z1), n(x1 - x0), n(y1 - y0))


def cylinder(part, radius, y0, y1, density, centre=(0.0, 0.0), least=12):
    """A cylinder's side about the vertical line through centre = (x, z), outward."""
    around = cells(2 * math.pi * radius, 2 * density, least)
    part.grid(lambda u, v: (centre[0] + radius * math.sin(2 * math.pi * u), lerp(y0, y1, v),
                            centre[1] + radius * math.cos(2 * math.pi * u)),
              around, cells(y1 - y0, density))


def floor(density, grout_cells):
    """Tiles (k x k cells each, alternating stones) and the grout sheet under them, grout_cells
    = (along z, along x) cells."""
    light, dark, grout = Part(), Part(), Part()
    k = cells(TILE - GROUT, density)
    for a in range(round(2 * HALF_W / TILE)):
        for b in range(round(2 * HALF_D / TILE)):
            x0, z0 = -HALF_W + a * TILE + GROUT / 2, -HALF_D + b * TILE + GROUT / 2
            s = TILE - GROUT
            (light if (a + b) % 2 == 0 else dark).grid(
                lambda u, v: (x0 + s * v, 0.0, z0 + s * u), k, k)
    grout.grid(lambda u, v: (lerp(-HALF_W, HALF_W, v), -0.005, lerp(-HALF_D, HALF_D, u)),
               *grout_cells)
    return [(light, "tile_light"), (dark, "tile_dark"), (grout, "grout")]


def walls(density):
    """The window wall (x = 6), the plain wall (x = -6), and the end walls with the vault's
    semicircular lunettes."""
    window, plain = Part(), Part()
    z_breaks = [-HALF_D]
    for z in WINDOW_Z:
        z_breaks += [z - WINDOW_HALF_W, z + WINDOW_HALF_W]
    z_breaks.append(HALF_D)
    holes = {(2 * k + 1, 1) for k in range(len(WINDOW_Z))}
    breaks_grid(window, lambda z, y: (HALF_W, y, z), z_breaks, [0.0, WINDOW_Y0, WINDOW_Y1,
                                                                 AISLE_H], density, holes)
    breaks_grid(plain, lambda y, z: (-HALF_W, y, z), [0.0, AISLE_H], [-HALF_D, HALF_D], density)
    ends = []
    for side in (-1.0, 1.0):
        end = Part()
        breaks_grid(end, lambda x, y: (x * side, y, side * HALF_D), [-HALF_W, HALF_W],
                    [0.0, AISLE_H], density)
        # The lunette under the vault: its rim through the vault's own edge vertices, so the two
        # meet without a crack.
        angles, _ = subdivide(vault_angles(), density, 2 * VAULT_R)
        end.fan((0.0, AISLE_H, side * HALF_D),
                [(VAULT_R * math.cos(a), AISLE_H + VAULT_R * math.sin(a), side * HALF_D)
                 for a in angles], cells(VAULT_R, density), closed=False)
        ends.append(end)
    return [(window, "plaster", "wall_windows"), (plain, "plaster", "wall_sconces"),
            (ends[0], "plaster", "wall_south"), (ends[1], "plaster", "wall_north")]


def vault_angles():
    """The vault's breaks in angle from +x: the springings and the skylight's edges (|x| = 1)."""
    edge = math.acos(SKYLIGHT_HALF_X / VAULT_R)
    return [0.0, edge, math.pi - edge, math.pi]


def ceilings(density):
    """The aisles' flat ceilings (over the arcade tops too) and the nave's barrel vault with the
    skylight opening at its crown."""
    out = []
    for side in (-1.0, 1.0):
        part = Part()
        breaks_grid(part, lambda z, x: (side * x, AISLE_H, z), [-HALF_D, HALF_D],
                    [VAULT_R, HALF_W], density)
        out.append((part, "ceiling", f"aisle_ceiling_{'west' if side < 0 else 'east'}"))
    vault = Part()
    # Around by arc length, twice as fine (curved).
    breaks_grid(vault, lambda a, z: (VAULT_R * math.cos(a), AISLE_H + VAULT_R * math.sin(a), z),
                vault_angles(), [-HALF_D, -SKYLIGHT_HALF_Z, SKYLIGHT_HALF_Z, HALF_D], density,
                holes={(1, 1)}, u_scale=2 * VAULT_R)
    out.append((vault, "ceiling", "vault"))
    return out


def column(density):
    part = Part()
    box(part, (-BASE_HALF, 0.0, -BASE_HALF), (BASE_HALF, BASE_H, BASE_HALF), density, "xXYzZ")
    cylinder(part, COLUMN_R, BASE_H, SPRING_Y - CAPITAL_H, density)
    box(part, (-CAPITAL_HALF, SPRING_Y - CAPITAL_H, -CAPITAL_HALF),
        (CAPITAL_HALF, SPRING_Y, CAPITAL_HALF), density, "xXyYzZ")
    return part


def arch_bay(density):
    """One bay of an arcade between two column centres 3 m apart (local z in [-1.5, 1.5], wall
    x in [-0.3, 0.3]): both spandrel faces, from the arch to the rectangle y in [5, 8], and the
    arch's underside (intrados)."""
    part = Part()
    half = 1.5
    # The outer boundary, right, top, left, in pieces whose cells are in proportion to length.
    sides = [(half, SPRING_Y, half, AISLE_H), (half, AISLE_H, -half, AISLE_H),
             (-half, AISLE_H, -half, SPRING_Y)]
    counts = [cells(math.hypot(z1 - z0, y1 - y0), density, 4) for z0, y0, z1, y1 in sides]
    outer = []
    for (z0, y0, z1, y1), n in zip(sides, counts):
        outer += [(lerp(z0, z1, k / n), lerp(y0, y1, k / n)) for k in range(n)]
    outer.append((-half, SPRING_Y))
    around = len(outer) - 1
    inner = [(ARCH_R * math.cos(math.pi * k / around), SPRING_Y + ARCH_R * math.sin(math.pi * k /
                                                                                  around))
             for k in range(around + 1)]
    radial = cells(AISLE_H - SPRING_Y - ARCH_R, density)
    for x in (-ARCADE_T / 2, ARCADE_T / 2):
        def point(u, v, x=x):
            k = round(u * around)
            (zi, yi), (zo, yo) = inner[k], outer[k]
            return (x, lerp(yi, yo, v), lerp(zi, zo, v))
        part.grid(point, around, radial)
    # The underside through the spandrels' inner vertices, so they meet without a crack.
    part.grid(lambda u, v: (lerp(-ARCADE_T / 2, ARCADE_T / 2, v),
                            *reversed(inner[round(u * around)])),
              around, cells(ARCADE_T, density))
    return part


def arcade_ends(density):
    part = Part()
    for x in (-ARCADE_X, ARCADE_X):
        for z in (COLUMN_Z[0], COLUMN_Z[-1]):
            part.grid(lambda u, v: (x + lerp(-ARCADE_T / 2, ARCADE_T / 2, u),
                                    lerp(SPRING_Y, AISLE_H, v), z),
                      cells(ARCADE_T, density), cells(AISLE_H - SPRING_Y, density))
    return part


def curtain(density):
    """One drape 0.8 m wide (local z in [0, 0.8]) from y = 6 down to 0.1 m over the floor:
    folds 0.2 m apart, 8 cm deep at the top, widening to 14 cm at the hem."""
    part = Part()
    width, top, hem = 0.8, 6.0, 0.1
    folds = width / 0.2
    part.grid(lambda u, v: (-(0.5 + 0.5 * math.sin(2 * math.pi * folds * u))
                            * lerp(0.14, 0.08, v), lerp(hem, top, v), width * u),
              cells(width, 4 * density, 4 * round(folds)), cells(top - hem, density))
    return part


def rod(density):
    part = Part()
    around = 8
    length = 2 * WINDOW_HALF_W + 1.2
    part.grid(lambda u, v: (0.02 * math.cos(2 * math.pi * u), 0.02 * math.sin(2 * math.pi * u),
                            lerp(-length / 2, length / 2, v)), around, cells(length, density))
    return part


def lamp(density):
    """A pendant: the cord up to the vault's crown, a conical shade (rim radius 0.35 m at local
    y = 0) and an emissive disc just inside the rim."""
    cord, shade, bulb = Part(), Part(), Part()
    crown = AISLE_H + VAULT_R - LAMP_Y
    cylinder(cord, 0.01, 0.3, crown, density, least=6)
    around = cells(2 * math.pi * 0.35, 2 * density, 16)
    shade.grid(lambda u, v: (lerp(0.35, 0.06, v) * math.sin(2 * math.pi * u), 0.3 * v,
                             lerp(0.35, 0.06, v) * math.cos(2 * math.pi * u)),
               around, cells(0.4, 2 * density, 2))
    bulb.fan((0.0, 0.03, 0.0), [(0.3 * math.sin(-2 * math.pi * k / around), 0.03,
                                 0.3 * math.cos(-2 * math.pi * k / around)) for k in range(around)],
             cells(0.3, 2 * density), closed=True)
    return [(cord, "cord"), (shade, "brass"), (bulb, "bulb")]


def sky_window():
    """The sky seen through a window: a panel 1 m outside it, 1 m larger each way. Its front
    faces out (+x); it lights the hall with its back face, through the material's doubleSided,
    as an exported emissive plane often does (docs/rendering.md, the final gather's lights)."""
    part = Part()
    half, y0, y1 = WINDOW_HALF_W + 1.0, WINDOW_Y0 - 1.0, WINDOW_Y1 + 1.0
    part.grid(lambda u, v: (0.0, lerp(y0, y1, u), lerp(-half, half, v)), 1, 1)
    return part


def sky_roof():
    part = Part()
    y = AISLE_H + VAULT_R + 0.8
    hx, hz = SKYLIGHT_HALF_X + 0.6, SKYLIGHT_HALF_Z + 0.6
    part.grid(lambda u, v: (lerp(-hx, hx, u), y, lerp(-hz, hz, v)), 1, 1)
    return part


def camera_rotation(direction):
    """The unit quaternion (x, y, z, w) turning a glTF camera (looking down -z, up +y) to look
    along `direction` with its up in the vertical plane: a yaw about y, then a pitch about x."""
    dx, dy, dz = direction
    yaw = math.atan2(-dx, -dz)
    pitch = math.atan2(dy, math.hypot(dx, dz))
    cy, sy, cp, sp = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(pitch / 2), math.sin(pitch / 2)
    return [cy * sp, sy * cp, -sy * sp, cy * cp]


def objects(density, grout_cells=(1, 1)):
    """(name, [(Part, material)], node transforms) for every object: one node per transform."""
    tiles_light, tiles_dark, grout = floor(density, grout_cells)
    out = [("floor_tiles", [tiles_light, tiles_dark], [{}]), ("grout", [grout], [{}])]
    out += [(name, [(p, m)], [{}]) for p, m, name in walls(density)]
    out += [(name, [(p, m)], [{}]) for p, m, name in ceilings(density)]
    out.append(("column", [(column(density), "stone")],
                [{"translation": [x, 0.0, z]} for x in (-ARCADE_X, ARCADE_X) for z in COLUMN_Z]))
    out.append(("arch", [(arch_bay(density), "stone")],
                [{"translation": [x, 0.0, z + 1.5]} for x in (-ARCADE_X, ARCADE_X)
                 for z in COLUMN_Z[:-1]]))
    out.append(("arcade_ends", [(arcade_ends(density), "stone")], [{}]))
    out.append(("curtain", [(curtain(density), "curtain")],
                [{"translation": [HALF_W - 0.12, 0.0, z + dz]} for z in WINDOW_Z
                 for dz in (-WINDOW_HALF_W - 0.5, WINDOW_HALF_W - 0.3)]))
    out.append(("curtain_rod", [(rod(density), "brass")],
                [{"translation": [HALF_W - 0.1, 6.05, z]} for z in WINDOW_Z]))
    out.append(("pendant", lamp(density),
                [{"translation": [0.0, LAMP_Y, z]} for z in LAMP_Z]))
    out.append(("sky_window", [(sky_window(), "sky")],
                [{"translation": [HALF_W + 1.0, 0.0, z]} for z in WINDOW_Z]))
    out.append(("sky_roof", [(sky_roof(), "sun_sky")], [{}]))
    return out


def triangle_count(scene):
    return sum(len(p.triangles) * len(nodes) for _, parts, nodes in scene for p, _ in parts)


def search(target):
    """The density and grout grid whose scene has about `target` triangles, and that scene: the
    largest density (bisection: the count only grows with it) whose scene with a one-cell grout
    sheet has at most `target` triangles, then the grout sheet (hidden under the tiles but for
    the gaps) cut into as many cells as make up the rest, 2:1 like the floor."""
    lo, hi = 0.05, math.sqrt(target / 3000.0)
    while triangle_count(objects(hi)) <= target:
        lo, hi = hi, 2 * hi
    for _ in range(14):
        middle = math.sqrt(lo * hi)
        lo, hi = (middle, hi) if triangle_count(objects(middle)) <= target else (lo, middle)
    rest = target - (triangle_count(objects(lo)) - 2)
    across = max(1, math.isqrt(max(rest, 4) // 4))
    grout_cells = (max(1, round(rest / (2 * across))), across)
    scene = objects(lo, grout_cells)
    return lo, triangle_count(scene), scene


def name_of(name, k):
    return name if k == 0 else f"{name}.{k:03d}"  # Blender's names of duplicates


def build(target):
    density, count, scene = search(target)
    builder = GltfBuilder()
    for name, parts, nodes in scene:
        prims = [(p.positions, MAT[m], p.indices()) for p, m in parts]
        mesh = builder.add_primitives(name, prims, node=False)
        for k, transform in enumerate(nodes):
            builder.add_node({"name": name_of(name, k), "mesh": mesh, **transform})
    lights = [{"name": "sconce", "type": "point", "color": [1.0, 0.78, 0.55], "intensity": 12.0}]
    for k, z in enumerate(SCONCE_Z):
        builder.add_node({"name": name_of("sconce", k), "translation": [-HALF_W + 0.25, 3.0, z],
                          "extensions": {"KHR_lights_punctual": {"light": 0}}})
    eye, target_point = (-1.6, 1.7, -11.2), (2.6, 4.2, 0.0)
    builder.add_node({"name": "camera", "camera": 0, "translation": list(eye),
                      "rotation": camera_rotation([b - a for a, b in zip(eye, target_point)])})
    cameras = [{"name": "camera", "type": "perspective",
                "perspective": {"yfov": 1.0, "aspectRatio": 1.5, "znear": 0.05, "zfar": 100.0}}]
    document = builder.document("large_interior", "DaisyRiot tools/make_large_interior.py",
                                MATERIALS, cameras)
    document["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_emissive_strength"]
    document["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
    document["asset"]["extras"] = {"triangles": count, "density": round(density, 6)}
    return builder, document, count, density


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--triangles", type=int, default=250000,
                        help="triangles to aim at (within 1%%; at least 5000)")
    parser.add_argument("-o", "--output", required=True, help="PATH.gltf (+ .bin) or PATH.glb")
    args = parser.parse_args()
    if args.triangles < 5000 or args.triangles > 5000000:
        parser.error("--triangles must be in [5000, 5000000]")
    if not args.output.endswith((".gltf", ".glb")):
        parser.error("-o must end in .gltf or .glb")
    builder, document, count, density = build(args.triangles)
    write_binary(args.output, builder, document)
    print(f"wrote {args.output}: {count} triangles (density {density:.3f} cells/m)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
