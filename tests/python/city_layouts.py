"""City layouts the demo must start on (issue 49, part 4), made at test time
from real buildings (never committed: they are ../shared/data/real's data).

    python tests/python/city_layouts.py spread OUT.city.json
    python tests/python/city_layouts.py far OUT.city.json
    python tests/python/city_layouts.py single OUT.city.json
    python tests/python/city_layouts.py holes OUT.city.json
    python tests/python/city_layouts.py lifted OUT.city.json
    python tests/python/city_layouts.py local OUT.city.json

Each takes real LoD2 buildings from zurich_subset_lod2.json (cjio's test data,
EPSG:2056, CityJSON 1.1) and writes a CityJSON 2.0 file:
- spread: 16 buildings in 4 clusters of 4 at the corners of a 500 m × 380 m
  rectangle (about 550 m × 430 m with the buildings), no terrain;
- far: 3 buildings 500 m apart (0,0 → 500,0 → 500,500), no terrain: the
  spread layout small enough for the demo to run to its end in CI;
- single: one building, no terrain;
- holes: 4 buildings 40 m apart on a TINRelief with a 30 m hole between them;
- lifted: the same 4 on a TINRelief 50 m below their bases (another datum);
- local: the spread layout moved to a local engineering frame (origin near
  0, 0) with no CRS.
"""
import copy
import json
import os
import sys
from pathlib import Path

REAL = Path(os.environ.get("SKYGROUND_REAL_DATA",
                           Path(__file__).resolve().parents[3] / "shared" / "data" / "real"))
ZURICH = "zurich_subset_lod2.json"
# The ids of the 16 buildings used, sorted: 8-25 m across, 6-27 m high.
BUILDINGS = 16


def _indices(b, out):
    if isinstance(b, list):
        for x in b:
            _indices(x, out)
    else:
        out.append(b)


def _remap(b, m):
    return [_remap(x, m) for x in b] if isinstance(b, list) else m[b]


def buildings(src):
    """Each root Building of `src` as (objects, real vertices), sorted by id."""
    objs, verts = src["CityObjects"], src["vertices"]
    s, t = src["transform"]["scale"], src["transform"]["translate"]
    out = []
    for bid in sorted(k for k, o in objs.items() if o["type"] == "Building"):
        ids = [bid] + objs[bid].get("children", [])
        used = []
        for i in ids:
            for g in objs[i].get("geometry", []):
                _indices(g["boundaries"], used)
        if not used:
            continue
        used = sorted(set(used))
        m = {v: k for k, v in enumerate(used)}
        part = {}
        for i in ids:
            o = copy.deepcopy(objs[i])
            for g in o.get("geometry", []):
                g["boundaries"] = _remap(g["boundaries"], m)
            part[i] = o
        real = [[verts[v][k] * s[k] + t[k] for k in range(3)] for v in used]
        out.append((part, real))
    return out


def placed(building, centre_xy, base_z):
    """`building` moved so its footprint box is centred on `centre_xy` and its lowest vertex is at `base_z`."""
    part, real = building
    lo = [min(p[k] for p in real) for k in range(3)]
    hi = [max(p[k] for p in real) for k in range(3)]
    d = [centre_xy[0] - (lo[0] + hi[0]) / 2, centre_xy[1] - (lo[1] + hi[1]) / 2, base_z - lo[2]]
    return part, [[p[k] + d[k] for k in range(3)] for p in real]


def model(pieces, crs="https://www.opengis.net/def/crs/EPSG/0/2056", extra_objects=None, extra_vertices=None):
    """A CityJSON 2.0 document of `pieces` (objects, real vertices) and extra
    objects indexing `extra_vertices` (real), with a millimetre transform."""
    all_real, objects = [], {}
    if extra_objects:
        pieces = list(pieces) + [(extra_objects, extra_vertices)]
    for part, real in pieces:
        base = len(all_real)
        for o in part.values():
            for g in o.get("geometry", []):
                g["boundaries"] = _remap(g["boundaries"], _Offset(base))
        objects.update(part)
        all_real += real
    origin = [min(p[k] for p in all_real) for k in range(3)]
    origin = [float(int(v // 1)) for v in origin]
    scale = [0.001, 0.001, 0.001]
    vertices = [[round((p[k] - origin[k]) / scale[k]) for k in range(3)] for p in all_real]
    lo = [min(p[k] for p in all_real) for k in range(3)]
    hi = [max(p[k] for p in all_real) for k in range(3)]
    metadata = {"geographicalExtent": lo + hi}
    if crs:
        metadata["referenceSystem"] = crs
    return {"type": "CityJSON", "version": "2.0", "transform": {"scale": scale, "translate": origin},
            "metadata": metadata, "CityObjects": objects, "vertices": vertices}


class _Offset:
    def __init__(self, base):
        self.base = base

    def __getitem__(self, i):
        return i + self.base


# Zurich's buildings, moved near the middle of the file's own area (LV95).
X0, Y0, Z0 = 2_682_000.0, 1_248_000.0, 410.0


def spread(src):
    """16 buildings, 4 clusters of 4 (2 × 2, 45 m apart) at the corners of a 500 m × 380 m rectangle."""
    bs = buildings(src)[:BUILDINGS]
    corners = [(0, 0, 0.0), (500, 0, 6.0), (0, 380, -4.0), (500, 380, 3.0)]
    pieces = []
    for c, (cx, cy, dz) in enumerate(corners):
        for k in range(4):
            x = X0 + cx + 45 * (k % 2)
            y = Y0 + cy + 45 * (k // 2)
            pieces.append(placed(bs[4 * c + k], (x, y), Z0 + dz))
    return model(pieces)


def far(src):
    """3 buildings 500 m apart, one per corner of an L (0,0 → 500,0 → 500,500)."""
    bs = buildings(src)[:3]
    corners = [(0, 0, 0.0), (500, 0, 5.0), (500, 500, -3.0)]
    return model([placed(b, (X0 + cx, Y0 + cy), Z0 + dz) for b, (cx, cy, dz) in zip(bs, corners)])


def single(src):
    """The first building alone."""
    return model([placed(buildings(src)[0], (X0, Y0), Z0)])


def _four(src):
    bs = buildings(src)[:4]
    return [placed(bs[k], (X0 + 40 * (k % 2), Y0 + 40 * (k // 2)), Z0) for k in range(4)]


def _tin(x0, y0, x1, y1, z, hole=None, step=10.0):
    """A TINRelief over [x0, x1] × [y0, y1] at height z, a triangle pair per
    `step` cell, the cells inside `hole` (x0, y0, x1, y1) left out."""
    verts, tris, index = [], [], {}

    def v(i, j):
        if (i, j) not in index:
            index[(i, j)] = len(verts)
            verts.append([x0 + i * step, y0 + j * step, z])
        return index[(i, j)]

    ni, nj = round((x1 - x0) / step), round((y1 - y0) / step)
    for j in range(nj):
        for i in range(ni):
            cx, cy = x0 + (i + 0.5) * step, y0 + (j + 0.5) * step
            if hole and hole[0] < cx < hole[2] and hole[1] < cy < hole[3]:
                continue
            a, b, c, d = v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)
            tris += [[[a, b, c]], [[a, c, d]]]
    obj = {"terrain_tin": {"type": "TINRelief",
                           "geometry": [{"type": "CompositeSurface", "lod": "1", "boundaries": tris}]}}
    return obj, verts


def holes(src):
    """4 buildings 40 m apart on a TINRelief (150 m square) with a 30 m hole in the middle, between them."""
    pieces = _four(src)
    tin, verts = _tin(X0 - 55, Y0 - 55, X0 + 95, Y0 + 95, Z0, hole=(X0 + 5, Y0 + 5, X0 + 35, Y0 + 35))
    return model(pieces, extra_objects=tin, extra_vertices=verts)


def lifted(src):
    """4 buildings on a TINRelief 50 m below their bases (a terrain in another vertical datum)."""
    pieces = _four(src)
    tin, verts = _tin(X0 - 55, Y0 - 55, X0 + 95, Y0 + 95, Z0 - 50.0)
    return model(pieces, extra_objects=tin, extra_vertices=verts)


def local(src):
    """The spread layout in a local engineering frame: x, y from about 0, z from 0, no CRS."""
    doc = spread(src)
    # The vertices are stored from the floored minimum: the model then runs from (20, 20, 0).
    doc["transform"]["translate"] = [20.0, 20.0, 0.0]
    del doc["metadata"]
    return doc


LAYOUTS = {"spread": spread, "far": far, "single": single, "holes": holes, "lifted": lifted, "local": local}


def write(name, out, real=REAL):
    """Writes layout `name` to `out`; returns `out`."""
    src = json.loads((Path(real) / ZURICH).read_text())
    Path(out).write_text(json.dumps(LAYOUTS[name](src)))
    return Path(out)


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in LAYOUTS:
        sys.exit(f"usage: {sys.argv[0]} {{{','.join(LAYOUTS)}}} OUT.city.json")
    write(sys.argv[1], sys.argv[2])
