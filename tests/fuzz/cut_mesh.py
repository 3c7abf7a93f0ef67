#!/usr/bin/env python3
"""Cuts the first FACES faces of an OBJ mesh into a small OBJ of its own (for the fuzz seeds and
assets in tests/fuzz): the vertices, texture coordinates and normals those faces use, renumbered.

usage: cut_mesh.py IN.obj FACES > OUT.obj
"""
import sys


def main() -> None:
    path, count = sys.argv[1], int(sys.argv[2])
    pools = {"v": [], "vt": [], "vn": []}
    faces = []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] in pools:
                pools[parts[0]].append(" ".join(parts[1:]))
            elif parts[0] == "f" and len(faces) < count:
                faces.append([corner.split("/") for corner in parts[1:]])
    # Renumber each kind in order of first use; OBJ indices start at 1.
    kinds = ["v", "vt", "vn"]
    used = {k: {} for k in kinds}
    out_faces = []
    for face in faces:
        corners = []
        for corner in face:
            fields = []
            for i, index in enumerate(corner):
                if not index:
                    fields.append("")
                    continue
                table = used[kinds[i]]
                table.setdefault(int(index), len(table) + 1)
                fields.append(str(table[int(index)]))
            corners.append("/".join(fields))
        out_faces.append("f " + " ".join(corners))
    print(f"# The first {len(faces)} faces of {path.rsplit('/', 1)[-1]} (tests/fuzz/cut_mesh.py)")
    for kind in kinds:
        for old, _ in sorted(used[kind].items(), key=lambda item: item[1]):
            print(f"{kind} {pools[kind][old - 1]}")
    print("\n".join(out_faces))


if __name__ == "__main__":
    main()
