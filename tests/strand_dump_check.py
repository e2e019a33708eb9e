#!/usr/bin/env python3
"""The render strands `loosehair simulate --dump-strands` writes, read back
by other readers (issue: strands).

Runs the scene for a few frames with a few hundred strands, then for each
frame reads strands_NNNNN.hair with the reader of strand_files_check.py
(the format's description, not the C++ reader) and strands_NNNNN.ply with
Open3D when installed: both must hold the strands the program printed, of
the asked number of points each, the same points in both, finite, the hair
moving between frames and every strand within 2% of its first frame's
length. Exit 0: passed; 1: failed; 77: Open3D missing (after the .hair
checks).
"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from strand_files_check import fail, read_hair  # noqa: E402


def lengths(points, counts):
    out, at = [], 0
    for c in counts:
        total = 0.0
        for k in range(at, at + c - 1):
            total += math.dist(points[k], points[k + 1])
        out.append(total)
        at += c
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--loosehair", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    frames, points_per = 4, 16
    cmd = [a.loosehair, "simulate", a.scene, "--frames", str(frames), "--dump-strands", a.work,
           "--strands", "400", "--strand-points", str(points_per)]
    print("$ " + " ".join(cmd), flush=True)
    res = subprocess.run(cmd, capture_output=True, text=True)
    print(res.stdout[-2000:], res.stderr[-2000:])
    if res.returncode != 0:
        fail("simulate failed")
    m = re.search(r"render strands: (\d+) of (\d+) points", res.stdout)
    if not m:
        fail("simulate did not report its render strands")
    strands = int(m.group(1))
    if int(m.group(2)) != points_per or not 300 <= strands <= 500:
        fail("unexpected strand report: " + m.group(0))
    try:
        import numpy as np
        import open3d as o3d
    except ImportError:
        o3d = None
    first_len, prev = None, None
    for f in range(1, frames + 1):
        base = os.path.join(a.work, "strands_%05d" % f)
        pts, counts = read_hair(base + ".hair")
        if len(counts) != strands or any(c != points_per for c in counts):
            fail("%s.hair: %d strands, counts %s" % (base, len(counts), sorted(set(counts))))
        if not all(math.isfinite(v) for p in pts for v in p):
            fail(base + ".hair: non-finite points")
        ls = lengths(pts, counts)
        if first_len is None:
            first_len = ls
        worst = max(abs(l / l0 - 1.0) for l, l0 in zip(ls, first_len))
        if worst > 0.02:
            fail("%s: a strand's length changed by %.3f from frame 1" % (base, worst))
        if prev is not None and max(math.dist(p, q) for p, q in zip(pts, prev)) < 1e-6:
            fail(base + ": the strands did not move from the frame before")
        prev = pts
        if o3d is not None:
            ls3 = o3d.io.read_line_set(base + ".ply")
            v = np.asarray(ls3.points)
            e = np.asarray(ls3.lines)
            if v.shape != (len(pts), 3) or e.shape != (strands * (points_per - 1), 2):
                fail("%s.ply: Open3D reads %s points and %s lines" % (base, v.shape, e.shape))
            if np.max(np.abs(v - np.asarray(pts))) > 1e-6:
                fail(base + ".ply and .hair hold different points")
        print("frame %d: %d strands, length change %.4f" % (f, strands, worst))
    if o3d is None:
        print("Open3D not installed: the .ply files were not read back")
        sys.exit(77)
    print("PASS")


if __name__ == "__main__":
    main()
