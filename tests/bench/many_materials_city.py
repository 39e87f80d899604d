#!/usr/bin/env python3
"""Writes a CityJSON 2.0 file shaped like the Den Haag example that showed one draw call per
material: 3412 box buildings (41k triangles) whose 20k surfaces cycle through 5971 materials of
three colours. `hlodr render FILE -o f.png` prints its draw calls and frame time.
Usage: many_materials_city.py OUT.city.json"""
import json
import sys

BUILDINGS, MATERIALS = 3412, 5971
COLOURS = [[0.8, 0.75, 0.7], [0.6, 0.2, 0.15], [0.35, 0.35, 0.35]]

vertices, objects, surface = [], {}, 0
for b in range(BUILDINGS):
    x, y = (b % 60) * 20, (b // 60) * 20
    h = 6 + (b * 7) % 25
    base = len(vertices)
    for dz in (0, h):
        vertices += [[x, y, dz], [x + 12, y, dz], [x + 12, y + 12, dz], [x, y + 12, dz]]
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    values = []
    for _ in faces:
        values.append(surface % MATERIALS)
        surface += 1
    objects["b%d" % b] = {"type": "Building", "geometry": [{
        "type": "Solid", "lod": "2",
        "boundaries": [[[[base + i for i in f]] for f in faces]],
        "material": {"colour": {"values": [values]}}}]}
doc = {"type": "CityJSON", "version": "2.0",
       "transform": {"scale": [1.0, 1.0, 1.0], "translate": [0.0, 0.0, 0.0]},
       "CityObjects": objects, "vertices": vertices,
       "appearance": {"materials": [{"name": "m%d" % i, "diffuseColor": COLOURS[i % 3]}
                                    for i in range(MATERIALS)]}}
with open(sys.argv[1], "w") as out:
    json.dump(doc, out)
