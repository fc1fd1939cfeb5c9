#!/usr/bin/env python3
"""Compares two one-channel PFM hit-distance images (glint's --hitdist x.pfm
and bench_embree's): hit/miss agreement and relative distance error."""
import sys
import numpy as np


def read_pf(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(b"\n", 3)
    assert parts[0].strip() == b"Pf", f"{path}: not a one-channel PFM"
    w, h = map(int, parts[1].split())
    scale = float(parts[2])
    dtype = "<f4" if scale < 0 else ">f4"
    return np.frombuffer(parts[3][: 4 * w * h], dtype=dtype).reshape(h, w)


a, b = read_pf(sys.argv[1]), read_pf(sys.argv[2])
hit_a, hit_b = np.isfinite(a), np.isfinite(b)
both = hit_a & hit_b
rel = np.abs(a[both] - b[both]) / np.maximum(np.abs(b[both]), 1e-30)
print(f"pixels={a.size}")
print(f"hits_a={hit_a.sum()} hits_b={hit_b.sum()}")
print(f"hit_disagreements={(hit_a != hit_b).sum()}")
print(f"rel_dist_err_max={rel.max() if rel.size else 0:.3e}")
print(f"rel_dist_err_p999={np.quantile(rel, 0.999) if rel.size else 0:.3e}")
print(f"pixels_rel_err_over_1e-4={(rel > 1e-4).sum()}")
