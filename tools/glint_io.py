"""What the Python tools share (tools/oidn-compare, tools/block-regression):
running this checkout's glint, FLIP from `glint compare`, PFM images, and
the octahedral normals glint's history textures keep."""

import os
import subprocess
import sys

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def glint(*args):
    """Runs glint (GLINT, or this checkout's release build) on the Vulkan
    backend unless WGPU_BACKEND says otherwise; its output, or exits."""
    exe = os.environ.get("GLINT", os.path.join(REPO, "target", "release", "glint"))
    env = dict(os.environ, WGPU_BACKEND=os.environ.get("WGPU_BACKEND", "vulkan"))
    out = subprocess.run([exe, *args], capture_output=True, text=True, env=env)
    if out.returncode != 0:
        sys.exit(f"glint {' '.join(args)} failed:\n{out.stderr}")
    return out.stdout + out.stderr


def flip(reference, image):
    """FLIP mean of `image` against `reference` (`glint compare`)."""
    for line in glint("compare", reference, image).splitlines():
        if line.startswith("flip_mean="):
            return float(line.split("=")[1])
    sys.exit("glint compare printed no flip_mean")


def read_pfm(path):
    """A PFM image as float32 rows top to bottom."""
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    channels = 3 if kind == b"PF" else 1
    return np.ascontiguousarray(data.reshape(h, w, channels)[::-1]).astype(np.float32)


def write_pfm(path, img):
    h, w, _ = img.shape
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(np.ascontiguousarray(img[::-1], dtype="<f4").tobytes())


def oct_to_normal(p):
    """Unit normals from octahedral pairs in [-1, 1] (shared/reproject.wgsl)."""
    n = np.concatenate([p, 1.0 - np.abs(p[..., :1]) - np.abs(p[..., 1:2])], axis=-1)
    fold = n[..., 2] < 0.0
    sign = np.where(n[..., :2] >= 0.0, 1.0, -1.0)
    n[..., :2] = np.where(fold[..., None], (1.0 - np.abs(n[..., 1::-1])) * sign, n[..., :2])
    return n / np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-12)


def geo_normal(geo):
    """The first hit's normal from the real-time graphs' `rt_geo`
    (octahedral in x and y, the hit distance in z, -1 on a miss: normal 0
    there)."""
    return np.where(geo[..., 2:3] < 0.0, 0.0, oct_to_normal(geo[..., :2].copy()))
