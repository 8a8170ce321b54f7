#!/usr/bin/python3
"""The deliberately naive model of BRAS CR2 that a visual route could produce: the mesh's
axis-aligned bounding box (room frame, z up), each of its six faces given the library
material a person would pick for what covers most of that face in the real room, and no
air absorption. Writes OUT/naive_room.yaml (room-model format of ../shared/DESIGN.md) and
OUT/measurements.yaml: the measurements with their positions moved into the box's frame
(whose corner is the mesh's minimum) and the naive room as the room to simulate.

    scripts/bras_naive_room.py data/bras_cr2/measured/measurements.yaml OUT

The AC3D file has y up; (x, y, z)_room = (x, -z, y)_file, as in measurements.yaml."""
import os
import sys

import yaml

# What each CR2 surface is (mat_CR2_description.txt and its photos' names), as the
# library names it. Not fitted to anything: the names a labeller would choose.
LIBRARY_NAME = {
    "concrete": "concrete_painted",
    "windows": "glass_window",
    "ceiling": "plasterboard_on_studs",
    "plaster": "plaster_smooth",
    "floor": "linoleum_on_concrete",
}


def polygons(path):
    """(material name, [room-frame vertices]) for every surface of the file."""
    lines = open(path).read().split("\n")
    materials, vertices, result = [], [], []
    i = 0
    while i < len(lines):
        words = lines[i].split()
        if words and words[0] == "MATERIAL":
            materials.append(words[1].strip('"'))
        elif words and words[0] == "numvert":
            vertices = []
            for k in range(int(words[1])):
                x, y, z = map(float, lines[i + 1 + k].split()[:3])
                vertices.append((x, -z, y))
            i += int(words[1])
        elif words and words[0] == "SURF":
            mat = int(lines[i + 1].split()[1])
            count = int(lines[i + 2].split()[1])
            refs = [int(lines[i + 3 + k].split()[0]) for k in range(count)]
            result.append((materials[mat], [vertices[r] for r in refs]))
            i += 2 + count
        i += 1
    return result


def area_and_normal(points):
    nx = ny = nz = 0.0
    for a, b in zip(points, points[1:] + points[:1]):
        nx += (a[1] - b[1]) * (a[2] + b[2])
        ny += (a[2] - b[2]) * (a[0] + b[0])
        nz += (a[0] - b[0]) * (a[1] + b[1])
    length = (nx * nx + ny * ny + nz * nz) ** 0.5
    return length / 2.0, (nx / length, ny / length, nz / length) if length > 0 else (0.0, 0.0, 0.0)


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: bras_naive_room.py MEASUREMENTS.yaml OUT_DIR")
    measurements_path, out = sys.argv[1], sys.argv[2]
    measurements = yaml.safe_load(open(measurements_path))
    mesh = os.path.join(os.path.dirname(os.path.abspath(measurements_path)), measurements["mesh"])
    polys = polygons(mesh)
    lo = [min(p[k] for _, ps in polys for p in ps) for k in range(3)]
    hi = [max(p[k] for _, ps in polys for p in ps) for k in range(3)]
    # Each face of the box takes the material with the most area among the polygons that
    # face the same way within 0.5 m of it (the surface a camera sees there).
    faces = {"floor": (2, lo[2]), "ceiling": (2, hi[2]), "wall_x_min": (0, lo[0]),
             "wall_x_max": (0, hi[0]), "wall_y_min": (1, lo[1]), "wall_y_max": (1, hi[1])}
    chosen = {}
    for face, (axis, value) in faces.items():
        areas = {}
        for material, points in polys:
            area, normal = area_and_normal(points)
            centre = sum(p[axis] for p in points) / len(points)
            if abs(normal[axis]) > 0.9 and abs(centre - value) < 0.5:
                kind = material.rsplit("_", 1)[-1]
                areas[kind] = areas.get(kind, 0.0) + area
        if not areas:
            sys.exit(f"no surface of the mesh lies on the box's {face}")
        chosen[face] = LIBRARY_NAME[max(areas, key=areas.get)]
    size = [h - l for l, h in zip(lo, hi)]
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "naive_room.yaml"), "w") as room:
        room.write("# The naive model of BRAS CR2 (scripts/bras_naive_room.py): the mesh's bounding box,\n"
                   "# library materials by name, no air absorption. Its corner (0, 0, 0) is\n"
                   f"# ({lo[0]:.4f}, {lo[1]:.4f}, {lo[2]:.4f}) in the frame of the BRAS measurements file.\n")
        room.write("frame: room\nroom_box:\n")
        room.write(f"  size_m: [{size[0]:.4f}, {size[1]:.4f}, {size[2]:.4f}]\n  has_ceiling: true\n")
        room.write("air: {enabled: false}\nsurfaces:\n")
        for face in faces:
            room.write(f"  {face}: {{material: {chosen[face]}}}\n")
    moved = {"room": "naive_room.yaml", "pairs": [], "parameters": measurements["parameters"]}
    for pair in measurements["pairs"]:
        shift = lambda p: [round(p[k] - lo[k], 4) for k in range(3)]
        moved["pairs"].append({"label": pair["label"], "source_m": shift(pair["source_m"]),
                               "receiver_m": shift(pair["receiver_m"])})
    with open(os.path.join(out, "measurements.yaml"), "w") as file:
        file.write("# BRAS CR2's measured parameters, positions in the naive box's frame "
                   "(scripts/bras_naive_room.py).\n")
        yaml.safe_dump(moved, file, default_flow_style=None, sort_keys=False)
    print(" ".join(f"{face}={chosen[face]}" for face in faces))

if __name__ == "__main__":
    main()
