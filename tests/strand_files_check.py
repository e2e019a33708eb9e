#!/usr/bin/env python3
"""Strand files as other programs read them (issue: styling, strand export).

`loosehair style STYLE --strands F` for F in .hair, .obj and .ply; then:
  - .hair read by this script's own reader of Cem Yuksel's layout (the
    file format's description, not the C++ reader),
  - .ply read by Open3D (read_line_set), when installed,
  - .obj read by Assimp (`assimp info`), when installed, and parsed here,
and every reader must give the same points and the same polylines. Last the
.hair file is imported as a style and simulated for a few frames.

Exit 0: passed; 1: failed; 77: no independent reader installed (skipped,
after the checks this script can do on its own).
"""
import argparse
import os
import re
import shutil
import struct
import subprocess
import sys


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def run(cmd):
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(r.stdout, end="")
    if r.returncode != 0:
        fail("%s exited with %d" % (cmd[0], r.returncode))
    return r.stdout


def read_hair(path):
    """points (list of float triples) and per-strand point counts."""
    with open(path, "rb") as f:
        b = f.read()
    if len(b) < 128 or b[:4] != b"HAIR":
        fail(path + ": no HAIR header")
    strands, points, flags, default_segments = struct.unpack_from("<4I", b, 4)
    at = 128
    if flags & 1:
        segments = struct.unpack_from("<%dH" % strands, b, at)
        at += 2 * strands
    else:
        segments = [default_segments] * strands
    counts = [s + 1 for s in segments]
    if sum(counts) != points:
        fail("%s: segments add up to %d points, header says %d" % (path, sum(counts), points))
    if not flags & 2:
        fail(path + ": no points array")
    xyz = struct.unpack_from("<%df" % (3 * points), b, at)
    return [xyz[3 * k:3 * k + 3] for k in range(points)], counts


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def read_obj(path):
    pts, lines = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                pts.append(tuple(f32(float(t)) for t in line.split()[1:4]))
            elif line.startswith("l "):
                lines.append([int(t) - 1 for t in line.split()[1:]])
    return pts, lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--loosehair", required=True)
    ap.add_argument("--style", required=True)
    ap.add_argument("--scene", required=True, help="a scene on the style's head")
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    out = {}
    for ext in ("hair", "obj", "ply"):
        path = os.path.join(a.work, "strands." + ext)
        text = run([a.loosehair, "style", a.style, "--strands", path])
        m = re.search(r"strands: (\d+), points: (\d+)", text)
        if not m:
            fail("no strand and point counts in the output")
        out[ext] = (path, int(m.group(1)), int(m.group(2)))
    path, n_strands, n_points = out["hair"]

    points, counts = read_hair(path)
    if len(counts) != n_strands or len(points) != n_points:
        fail(".hair: %d strands, %d points; loosehair printed %d, %d"
             % (len(counts), len(points), n_strands, n_points))
    # consecutive points of a strand, as (i, i + 1) index pairs
    edges = []
    first = 0
    for c in counts:
        edges.extend((j, j + 1) for j in range(first, first + c - 1))
        first += c
    print(".hair (own reader): %d strands, %d points" % (n_strands, n_points))

    obj_points, obj_lines = read_obj(out["obj"][0])
    if obj_points != points:
        fail(".obj points differ from the .hair points")
    if [len(l) for l in obj_lines] != counts or any(l != list(range(l[0], l[0] + len(l))) for l in obj_lines):
        fail(".obj polylines differ from the .hair strands")
    print(".obj (parsed here): the same points and polylines")

    independent = 0
    try:
        import numpy as np
        import open3d as o3d
    except ImportError:
        print("Open3D is not installed: .ply not read by it")
    else:
        ls = o3d.io.read_line_set(out["ply"][0])
        p = np.asarray(ls.points)
        l = np.asarray(ls.lines)
        if p.shape != (n_points, 3) or l.shape != (len(edges), 2):
            fail(".ply in Open3D: %s points, %s lines; expected %d, %d"
                 % (p.shape, l.shape, n_points, len(edges)))
        if not np.array_equal(p.astype(np.float32), np.asarray(points, dtype=np.float32)):
            fail(".ply points in Open3D differ from the .hair points")
        if not np.array_equal(l, np.asarray(edges)):
            fail(".ply edges in Open3D differ from the .hair strands")
        print(".ply (Open3D %s): the same points and segments" % o3d.__version__)
        independent += 1

    assimp = shutil.which("assimp")
    if not assimp:
        print("assimp is not installed: .obj not read by it")
    else:
        info = run([assimp, "info", out["obj"][0]])
        v = re.search(r"Vertices:\s+(\d+)", info)
        f = re.search(r"Faces:\s+(\d+)", info)
        t = re.search(r"Primitive Types:\s+(\S+)", info)
        if not (v and f and t) or int(v.group(1)) != n_points or int(f.group(1)) != len(edges) \
                or t.group(1) != "lines":
            fail(".obj in Assimp: not %d vertices and %d line segments" % (n_points, len(edges)))
        print(".obj (Assimp): %d vertices, %d line segments" % (n_points, len(edges)))
        independent += 1

    # the .hair groom, imported and simulated
    style = os.path.join(a.work, "imported.json")
    if os.path.exists(style):
        os.remove(style)
    text = run([a.loosehair, "style", "--import", path, "--head", a.scene, "--out", style])
    if not re.search(r"%d kept" % n_strands, text):
        fail("the import did not keep every strand")
    text = run([a.loosehair, "simulate", a.scene, "--style", style, "--frames", "6"])
    if not re.search(r"state-hash: [0-9a-f]{16}", text):
        fail("the imported groom did not simulate")
    print("the imported groom simulates")

    if independent == 0:
        print("SKIPPED: no independent reader (python3-open3d, assimp-utils) is installed")
        sys.exit(77)
    print("PASSED")


if __name__ == "__main__":
    main()
