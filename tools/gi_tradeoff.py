#!/usr/bin/python3
"""@brief The light tree against RSM sampling at equal error (issue 9): time against error of both gathers, error
measured against `gi.mode=exact` on the same views, scene and RSM (the sum both approximate).

Every point is one `fovea run` (the same views at scene time 0): the shade pass's median GPU time over the timed
frames, the clusters (tree nodes, samples) per pixel the shading pass measured on the GPU (the run's `gi`
`clusters_per_pixel_mean` / `_max`, every mode), and the indirect light alone (`--view gi`, linear PFM) compared
with the exact sum's by `fovea compare` (relative L1: sum |a - b| / sum |b| over both eyes and the three channels).
The points are run round-robin --repeats times (so load on the machine hits every method alike) and the median time is kept. Then, for each tree point, RSM sampling's time and
sample count at the same error are interpolated (log-log, between the two sampling points around that error) and
the speed-up is sampling's time over the tree's, for the whole shade pass and for the gather alone (the shade pass
minus its time with GI off, timed in the same rounds: both methods share the direct light). A tree point whose error is outside the sampling curve's range is
reported as such, not extrapolated.

usage: tools/gi_tradeoff.py [--fovea BIN] [--scene NAME] [--eye-size WxH] [--rsm N] [--frames N] [--repeats N]
                            [--samples S1,S2,...] [--limits L1,...] [--thresholds D:N,...] [--refines R,...]
                            [--bound F,...] [--view gi|color] [--set NAME=VALUE]... [--truth-spp N] [--stat median|min]
                            [--no-sampling] [--out DIR] [--plot PNG]
       tools/gi_tradeoff.py --replot DIR/gi_tradeoff.json --plot PNG   (redraw a finished run's plot)

--plot draws, by gnuplot, shade-pass time against relative L1 (log-log) for RSM sampling (a curve over its sample
counts) and the tree's points, with the speed-up at equal error written beside each tree point.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys

import numpy as np


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.stderr.write("gi_tradeoff: failed (%d): %s\n%s\n" % (p.returncode, " ".join(cmd), p.stderr[-2000:]))
        sys.exit(1)
    return p.stdout


def pfm_of(d):
    files = sorted(f for f in os.listdir(d) if f.endswith(".pfm"))
    if not files:
        sys.stderr.write("gi_tradeoff: no PFM in %s\n" % d)
        sys.exit(1)
    return os.path.join(d, files[-1])


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(h, w, 3 if kind == b"PF" else 1).astype(np.float64)


def rel_l1(a, b):
    """sum |a - b| / sum |b| over every pixel and channel (both eyes): the relative L1 error of the image."""
    return float(np.abs(a - b).sum() / max(np.abs(b).sum(), 1e-30))


def interp(points, err):
    """points: [(error, time, samples)] of RSM sampling. Log-log interpolation at err, or None outside the range."""
    pts = sorted(points)
    for (e0, t0, s0), (e1, t1, s1) in zip(pts, pts[1:]):
        if e0 <= err <= e1 and e0 > 0 and e1 > e0:
            a = (math.log(err) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return (math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0))),
                    math.exp(math.log(s0) + a * (math.log(s1) - math.log(s0))))
    return None


def plot(res, png):
    """Shade-pass time against relative L1 vs exact (log-log): RSM sampling as a curve, the tree as points, each
    labelled with its speed-up at equal error; the GI-off time (direct light, in both) as a line."""
    pts = res["points"]
    samp = sorted((p["rel_l1"], p["shade_ms"], p["samples"]) for p in pts if p["method"] == "rsm_sampling")
    tree = [p for p in pts if p["method"] == "cut"]
    if not samp and not tree:
        sys.stderr.write("gi_tradeoff: nothing to plot\n")
        sys.exit(1)
    dat = png + ".dat"
    with open(dat, "w") as f:
        f.write("# RSM sampling: rel_l1 shade_ms samples\n")
        for e, t, s in samp:
            f.write("%g %g %d\n" % (e, t, s))
        f.write("\n\n# tree: rel_l1 shade_ms speed-up (0: outside the sampling curve)\n")
        for p in tree:
            f.write("%g %g %g \"%s\"\n" % (p["rel_l1"], p["shade_ms"], p.get("speedup", 0.0),
                                           p["label"].replace("cut limit ", "L").replace(" thr ", " ")
                                           .replace(" refine ", " t")))
    a = res["args"]
    title = "%s %s per eye, RSM %d: shade pass (%s of %d rounds) against error vs exact" % (
        a["scene"], a["eye_size"], a["rsm"], a["stat"], a["repeats"])
    off = res.get("gi_off_shade_ms")
    script = "\n".join([
        "set terminal pngcairo size 900,600 noenhanced" if gnuplot_has("pngcairo") else "set terminal png size 900,600",
        "set output '%s'" % png,
        "set title '%s'" % title,
        "set logscale xy", "set grid",
        "set xlabel 'relative L1 of the indirect light vs gi.mode=exact'",
        "set ylabel 'shade pass, ms (direct light + the gather)'",
        "set key top left",
        "set xrange [*:*] reverse",
        ("set arrow from graph 0, first %g to graph 1, first %g nohead dt 2 lc rgb 'gray40'\n"
         "set label 'GI off (direct light alone): %.0f ms' at graph 0.02, first %g offset 0,0.7 tc rgb 'gray40'"
         % (off, off, off, off) if off and off == off else ""),
        "plot '%s' index 0 using 1:2 with linespoints pt 7 lw 2 lc rgb '#c0392b' title 'RSM sampling (samples)', "
        "'' index 0 using 1:2:(sprintf('%%d', $3)) with labels offset 0,1 tc rgb '#c0392b' notitle, "
        "'' index 1 using 1:2 with points pt 5 ps 1.5 lc rgb '#2471a3' title 'light tree (speed-up at equal error)', "
        "'' index 1 using 1:2:($3 > 0 ? sprintf('%%.1fx', $3) : '') with labels offset 0,-1.2 tc rgb '#2471a3' "
        "notitle" % dat,
    ])
    p = subprocess.run(["gnuplot"], input=script, text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if p.returncode != 0:
        sys.stderr.write("gi_tradeoff: gnuplot failed: %s\n" % p.stderr[-2000:])
        sys.exit(1)
    print("plot: %s" % png)


def gnuplot_has(term):
    p = subprocess.run(["gnuplot", "-e", "set terminal %s" % term], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    return p.returncode == 0 and not p.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fovea", default="build/release/tools/fovea/fovea")
    ap.add_argument("--scene", default="cornell")
    ap.add_argument("--eye-size", default="48x48")
    ap.add_argument("--rsm", type=int, default=256)
    ap.add_argument("--frames", type=int, default=3)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--samples", default="64,128,256,512,1024,2048,4096")
    ap.add_argument("--limits", default="16,32,64,leaf")
    ap.add_argument("--thresholds", default="0.25:0.6,0.05:0.9")
    ap.add_argument("--refines", default="0", help="gi.refine values of the cut points")
    ap.add_argument("--bound", default="", help="gi.bound_fraction values of gi.mode=bound points")
    ap.add_argument("--view", default="gi", choices=["gi", "color"])
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--out", default="out/gi_tradeoff")
    ap.add_argument("--truth-spp", type=int, default=0,
                    help="also measure each point's colour against `fovea reference --mode path --bounces 1` at "
                         "this many samples per pixel (the physical one-bounce truth), and exact's and GI off's")
    ap.add_argument("--no-sampling", action="store_true", help="only the tree's points")
    ap.add_argument("--stat", default="median", choices=["median", "min"],
                    help="each point's time over the repeats: median, or min (the least disturbed round on a "
                         "shared machine: load only adds time)")
    ap.add_argument("--plot", default="", help="also draw time against error to this PNG (gnuplot)")
    ap.add_argument("--replot", default="", help="only redraw --plot from a finished run's gi_tradeoff.json")
    a = ap.parse_args()
    if a.replot:
        if not a.plot:
            ap.error("--replot needs --plot PNG")
        with open(a.replot) as f:
            plot(json.load(f), a.plot)
        return

    base = [a.fovea, "run", "--scene", a.scene, "--eye-size", a.eye_size, "--quality", "balanced",
            "--set", "fovea.enabled=off", "--set", "distort.enabled=off", "--set", "gi.rsm_size=%d" % a.rsm]
    for s in a.set:
        base += ["--set", s]
    points = []
    for thr in a.thresholds.split(","):
        d, n = thr.split(":")
        for ref in a.refines.split(","):
            for lim in a.limits.split(","):
                points.append({"method": "cut", "label": "cut limit %s thr %s/%s%s" % (
                                   lim, d, n, " refine " + ref if float(ref) > 0 else ""),
                               "sets": ["gi.mode=cut", "gi.limit_level=" + lim, "gi.depth_threshold=" + d,
                                        "gi.normal_threshold=" + n, "gi.refine=" + ref]})
    for f in (a.bound.split(",") if a.bound else []):
        points.append({"method": "cut", "label": "bound %s" % f, "sets": ["gi.mode=bound", "gi.bound_fraction=" + f]})
    for s in ([] if a.no_sampling else a.samples.split(",")):
        points.append({"method": "rsm_sampling", "label": "rsm_sampling %s" % s, "samples": int(s),
                       "sets": ["gi.mode=rsm_sampling", "gi.samples=" + s]})
    os.makedirs(a.out, exist_ok=True)

    def render(sets, d, frames, view):
        cmd = base + sum([["--set", s] for s in sets], []) + ["--frames", str(frames), "--view", view, "--json"]
        if d:
            cmd += ["--out", d, "--float"]
        return json.loads(run(cmd))

    exact_dir = os.path.join(a.out, "exact")
    ej = render(["gi.mode=exact"], exact_dir, 1, a.view)
    exact_pfm = pfm_of(exact_dir)
    exact_img = read_pfm(exact_pfm)
    shade = lambda j: next(p["gpu_ms_median"] for p in j["passes"] if p["name"] == "shade")
    per_pixel = lambda p: ("%.1f (max %.0f)" % (p["clusters"], p["clusters_max"])
                           if p.get("clusters") is not None else "not measured")
    print("exact: %d lit VPLs (measured: %s per pixel), shade %.1f ms"
          % (ej["gi"]["lit_vpls"], per_pixel({"clusters": ej["gi"]["clusters_per_pixel_mean"],
                                               "clusters_max": ej["gi"]["clusters_per_pixel_max"]}), shade(ej)),
          flush=True)
    for i, p in enumerate(points):
        d = os.path.join(a.out, "p%02d" % i)
        j = render(p["sets"], d, 1, a.view)
        c = json.loads(run([a.fovea, "compare", pfm_of(d), exact_pfm, "--json"]))
        p["rel_l1"] = rel_l1(read_pfm(pfm_of(d)), exact_img)
        p["psnr_db"] = c["psnr_db"]
        p["ssim"] = c["ssim"]
        p["clusters"] = j["gi"]["clusters_per_pixel_mean"]
        p["clusters_max"] = j["gi"]["clusters_per_pixel_max"]
        print("%s: %.4f, %s clusters per pixel" % (p["label"], p["rel_l1"], per_pixel(p)), flush=True)
        p["times"] = []
    truth = None
    if a.truth_spp:
        tdir = os.path.join(a.out, "truth")
        run([a.fovea, "reference", "--scene", a.scene, "--mode", "path", "--bounces", "1", "--spp", str(a.truth_spp),
             "--eye-size", a.eye_size, "--out", tdir])
        truth = read_pfm(pfm_of(tdir))
        for label, sets in (("exact", ["gi.mode=exact"]), ("off", ["gi.enabled=off"])):
            d = os.path.join(a.out, "truth_" + label)
            render(sets, d, 1, "color")
            print("colour vs the path-traced truth: GI %s %.4f" % (label, rel_l1(read_pfm(pfm_of(d)), truth)))
        for i, p in enumerate(points):
            d = os.path.join(a.out, "c%02d" % i)
            render(p["sets"], d, 1, "color")
            p["rel_l1_vs_truth"] = rel_l1(read_pfm(pfm_of(d)), truth)
    # GI off: the shade pass without the gather (direct light only), timed in the same rounds, so that the
    # gather's own time (shade - off) can be compared as well as the whole pass's.
    off = {"sets": ["gi.enabled=off"], "times": []}
    for r in range(a.repeats):
        for p in points + [off]:
            p["times"].append(shade(render(p["sets"], None, a.frames, a.view)))
    for p in points + [off]:
        p["shade_ms"] = (min if a.stat == "min" else statistics.median)(p["times"]) if p["times"] else float("nan")
    off_ms = off["shade_ms"]
    gather = lambda ms: max(ms - off_ms, 1e-3) if off_ms == off_ms else float("nan")
    samp = [(p["rel_l1"], p["shade_ms"], p["samples"]) for p in points if p["method"] == "rsm_sampling"]
    samp_g = [(p["rel_l1"], gather(p["shade_ms"]), p["samples"]) for p in points if p["method"] == "rsm_sampling"]
    print("GI off (direct light only): shade %.1f ms (%s of %d)" % (off_ms, a.stat, a.repeats))
    print("| point | clusters, nodes or samples per pixel (measured: mean, max) | shade ms (%s of %d) | "
          "relative L1 vs exact | PSNR dB | "
          "sampling at equal error: samples, ms | speed-up (shade) | speed-up (gather = shade - GI off) |%s"
          % (a.stat, a.repeats, " colour vs path truth |" if truth is not None else ""))
    print("| --- | --- | --- | --- | --- | --- | --- | --- |%s" % (" --- |" if truth is not None else ""))
    for p in points:
        extra = ""
        if p["method"] == "cut":
            m = interp(samp, p["rel_l1"])
            mg = interp(samp_g, p["rel_l1"])
            if m and mg:
                p["equal_error_samples"], p["equal_error_ms"] = m[1], m[0]
                p["speedup"] = m[0] / p["shade_ms"]
                p["speedup_gather"] = mg[0] / gather(p["shade_ms"])
                extra = "%.0f, %.1f | **%.2fx** | %.2fx" % (m[1], m[0], p["speedup"], p["speedup_gather"])
            else:
                extra = "outside the sampling curve | — | —"
        else:
            extra = "— | — | —"
        if truth is not None:
            extra += " | %.4f" % p["rel_l1_vs_truth"]
        print("| %s | %s | %.1f | %.4f | %.2f | %s |" % (p["label"], per_pixel(p), p["shade_ms"], p["rel_l1"],
                                                         p["psnr_db"], extra))
    with open(os.path.join(a.out, "gi_tradeoff.json"), "w") as f:
        json.dump({"args": vars(a), "exact_shade_ms": shade(ej), "lit_vpls": ej["gi"]["lit_vpls"],
                   "gi_off_shade_ms": off_ms, "points": points}, f, indent=1)
    if a.plot:
        with open(os.path.join(a.out, "gi_tradeoff.json")) as f:
            plot(json.load(f), a.plot)


if __name__ == "__main__":
    main()
