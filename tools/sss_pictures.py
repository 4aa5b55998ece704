#!/usr/bin/python3
"""The translucent-material pictures of docs/techniques.md, from fovea's own commands on the default settings
(balanced, the generic HMD's lens), the left eye at 240x270, 8 frames so the saved frame has its temporal history:
  docs/img/sss_cornell_view.png: cornell-translucent, the colour and --view sss (x4);
  docs/img/sss_bunny_view.png:   scenes/marble-bunny.scene.json opaque (sss.enabled=off), translucent, --view sss.
Usage: tools/sss_pictures.py [path/to/fovea]   (Debian's python3: numpy, PIL)"""
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOVEA = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build/release/tools/fovea/fovea")


def left_eye(tmp, name, scene, *args):
    out = os.path.join(tmp, name)
    subprocess.run([FOVEA, "run", "--scene", scene, "--frames", "8", "--eye-size", "240x270", "--layout", "eyes",
                    "--out", out, *args], check=True, stdout=subprocess.DEVNULL, timeout=600)
    return np.asarray(Image.open(os.path.join(out, "frame_00007_left.png")).convert("RGB"))


def save(panels, path):
    Image.fromarray(np.concatenate(panels, axis=1)).save(os.path.join(ROOT, path))
    print(path)


with tempfile.TemporaryDirectory() as tmp:
    save([left_eye(tmp, "c", "cornell-translucent"),
          left_eye(tmp, "cs", "cornell-translucent", "--view", "sss", "--exposure", "4")], "docs/img/sss_cornell_view.png")
    bunny = os.path.join(ROOT, "scenes/marble-bunny.scene.json")
    save([left_eye(tmp, "bo", bunny, "--set", "sss.enabled=off"), left_eye(tmp, "bt", bunny),
          left_eye(tmp, "bs", bunny, "--view", "sss")], "docs/img/sss_bunny_view.png")
