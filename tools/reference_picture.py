#!/usr/bin/python3
"""The README's "Reference images" picture, from the README's own recipe on the default settings (issue 24):
`fovea run --quality exact` and `fovea reference --quality exact` at the same size, then the left eye of each PNG
(through the default HMD's lens) and their difference x 10, side by side.

    tools/reference_picture.py [--fovea build/release/tools/fovea/fovea] [--eye-size 160x180]
                               [--out docs/img/cornell_gpu_reference_difference.png]

Prints the PSNR/SSIM `fovea compare` gives for the PNGs and the PFMs. Needs Debian's python3-numpy and
python3-skimage (tools/install-deps.sh)."""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from skimage import io


def run(cmd, timeout=1800):
    print("+", " ".join(cmd), file=sys.stderr)
    return subprocess.run(cmd, check=True, capture_output=True, text=True, timeout=timeout).stdout


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fovea", default=os.path.join(root, "build/release/tools/fovea/fovea"))
    ap.add_argument("--eye-size", default="160x180")
    ap.add_argument("--out", default=os.path.join(root, "docs/img/cornell_gpu_reference_difference.png"))
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        gpu, ref = os.path.join(tmp, "gpu"), os.path.join(tmp, "ref")
        run([a.fovea, "run", "--eye-size", a.eye_size, "--out", gpu, "--float", "--quality", "exact"])
        run([a.fovea, "reference", "--eye-size", a.eye_size, "--out", ref, "--quality", "exact"])
        for ext in ("png", "pfm"):
            j = json.loads(run([a.fovea, "compare", f"{gpu}/frame_00000.{ext}", f"{ref}/frame_00000.{ext}",
                                "--json"]))
            print(f"{ext}: PSNR {j['psnr_db']:.2f} dB, SSIM {j['ssim']:.5f}")
        g = io.imread(f"{gpu}/frame_00000.png")[..., :3].astype(np.float64)
        r = io.imread(f"{ref}/frame_00000.png")[..., :3].astype(np.float64)
    w = g.shape[1] // 2
    g, r = g[:, :w], r[:, :w]  # the left eyes
    diff = np.clip(np.abs(g - r) * 10.0, 0, 255)
    gap = np.full((g.shape[0], 4, 3), 255.0)
    io.imsave(a.out, np.concatenate([g, gap, r, gap, diff], axis=1).astype(np.uint8), check_contrast=False)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
