"""Writes each root Building of a CityJSON file (with its BuildingParts) to a
CityJSON file of its own, vertices renumbered, so a city model spread over
kilometres (zurich_subset_lod2.json: 49 buildings over ~9 x 10 km) can be
surveyed building by building with `skyground aerial --scene OUT/b_NN.json`.

Usage: python3 cityjson_per_building.py MODEL.json OUT_DIR"""
import copy
import json
import sys
from pathlib import Path


def vertex_ids(objects, oid):
    """Every vertex index used by `oid` and its children."""
    out = []

    def walk(x):
        if isinstance(x, list):
            for y in x:
                walk(y)
        else:
            out.append(x)

    for g in objects[oid].get("geometry", []):
        walk(g["boundaries"])
    for c in objects[oid].get("children", []):
        out += vertex_ids(objects, c)
    return out


def main(model, out_dir):
    d = json.loads(Path(model).read_text())
    objects = d["CityObjects"]
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    roots = sorted(k for k, v in objects.items() if v["type"] == "Building")
    for n, b in enumerate(roots):
        used = sorted(set(vertex_ids(objects, b)))
        if not used:
            continue
        remap = {old: new for new, old in enumerate(used)}

        def renumber(x):
            return [renumber(y) for y in x] if isinstance(x, list) else remap[x]

        doc = {k: v for k, v in d.items() if k not in ("CityObjects", "vertices")}
        doc["vertices"] = [d["vertices"][i] for i in used]
        doc["CityObjects"] = {}
        for k in [b, *objects[b].get("children", [])]:
            o = copy.deepcopy(objects[k])
            for g in o.get("geometry", []):
                g["boundaries"] = renumber(g["boundaries"])
            doc["CityObjects"][k] = o
        (out_dir / f"b_{n:02d}.json").write_text(json.dumps(doc))


if __name__ == "__main__":
    main(*sys.argv[1:3])
