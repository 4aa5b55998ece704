#!/usr/bin/python3
"""@brief Frame time against periphery SSIM of the reconstruction fills (issue 25): `fovea bench --sweep
fovea.recon=...` with the gaze at the view centre measures every fill against full-resolution shading of the same
model (per eccentricity band); this plots each fill's frame time (median GPU ms of the frame) and reconstruct pass
time against the SSIM of the periphery (the bands from --from-deg out, pixel-weighted) by gnuplot.

usage: tools/fovea_recon_plot.py [--fovea BIN] [--eye-size WxH] [--frames N] [--fills nearest,sibson,idw,soft]
                                 [--from-deg D] [--set NAME=VALUE]... [--out DIR] [--plot PNG]
       tools/fovea_recon_plot.py --replot DIR/bench.json --plot PNG
"""
import argparse
import json
import os
import subprocess
import sys


def points(bench, from_deg):
    out = []
    for p in bench["points"]:
        vf = p.get("vs_full_resolution")
        if not vf or not vf.get("bands"):
            continue
        bands = [b for b in vf["bands"] if b["from_deg"] >= from_deg and b["pixels"] > 0]
        n = sum(b["pixels"] for b in bands)
        ssim = sum(b["ssim"] * b["pixels"] for b in bands) / n if n else float("nan")
        passes = p["passes"]
        recon = passes.get("reconstruct", {}).get("median_ms") if isinstance(passes, dict) else None
        out.append((p["knobs"].get("fovea.recon", "?"), p["frame_ms"]["median_ms"], recon, ssim))
    return out


def plot(pts, from_deg, png):
    dat = png + ".dat"
    with open(dat, "w") as f:
        f.write("# fill frame_ms reconstruct_ms periphery_ssim\n")
        for name, frame, recon, ssim in pts:
            f.write(f"{name} {frame:.3f} {recon if recon is not None else float('nan'):.3f} {ssim:.6f}\n")
    gp = f"""set terminal pngcairo size 900,560
set output '{png}'
set title 'Reconstruction fills: time against periphery SSIM vs full resolution (> {from_deg:g} deg)' noenhanced
set xlabel 'SSIM vs full-resolution shading, periphery (pixel-weighted bands)'
set ylabel 'GPU ms (median)'
set key top right
set grid
plot '{dat}' using 4:2 with points pt 7 ps 1.5 title 'frame', \\
     '' using 4:2:1 with labels offset 1.5,0.8 notitle, \\
     '' using 4:3 with points pt 5 ps 1.2 title 'reconstruct pass', \\
     '' using 4:3:1 with labels offset 1.5,-0.8 notitle
"""
    subprocess.run(["gnuplot"], input=gp, text=True, check=True, timeout=120)
    os.remove(dat)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fovea", default=os.path.join(here, "..", "build", "release", "tools", "fovea", "fovea"))
    ap.add_argument("--eye-size", default="720x800")
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--fills", default="nearest,sibson,idw,soft")
    ap.add_argument("--from-deg", type=float, default=20.0)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--out", default="out/recon_bench")
    ap.add_argument("--plot", default=os.path.join(here, "..", "docs", "img", "fovea_recon_tradeoff.png"))
    ap.add_argument("--replot")
    a = ap.parse_args()
    if a.replot:
        with open(a.replot) as f:
            bench = json.load(f)
    else:
        cmd = [a.fovea, "bench", "--sweep", "fovea.recon=" + a.fills, "--gaze-deg", "0,0", "--frames",
               str(a.frames), "--eye-size", a.eye_size, "--exact", "off", "--reference", "none", "--out", a.out]
        for s in a.set:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, timeout=7200)
        with open(os.path.join(a.out, "bench.json")) as f:
            bench = json.load(f)
    pts = points(bench, a.from_deg)
    if not pts:
        sys.exit("no foveated point with per-band errors against full resolution")
    print(f"fill     frame ms  reconstruct ms  SSIM > {a.from_deg:g} deg")
    for name, frame, recon, ssim in pts:
        print(f"{name:8s} {frame:9.1f}  {recon if recon is not None else float('nan'):14.1f}  {ssim:.5f}")
    plot(pts, a.from_deg, a.plot)
    print(a.plot)


if __name__ == "__main__":
    main()
