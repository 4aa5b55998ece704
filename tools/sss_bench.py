#!/usr/bin/python3
"""Subsurface scattering: the light hierarchy's time and error against the exact dipole sum (BENCHMARKS.md).

usage: tools/sss_bench.py [--fovea PATH] [--scene S] [--eye-size WxH] [--frames N] [--reps R] [--out DIR]
                          NAME='--set k=v ...' ...
The first NAME is the reference (normally NAME='--set sss.mode=exact'). The configurations are run in turn, R times
(alternated, so load drift hits them alike), each as `fovea run --view sss --float` with GI and the lens off (the
shading pass is then direct light plus the subsurface term). Time: the sss + shade passes' median GPU ms per run,
the median over the R runs, and the speed-up against the reference's (ratios within one invocation only). Error:
sum |h - e| / sum e of the subsurface term alone (the last frame's linear PFM) against the reference's image; pixels
without subsurface light are 0 in both, so this is the mean relative error over the translucent pixels. Any NaN/Inf
or validation message fails the run. Prints a Markdown table."""
import json, os, statistics, subprocess, sys

import numpy as np


def pfm(path):
    with open(path, 'rb') as f:
        if f.readline().strip() != b'PF':
            raise SystemExit(f'{path}: not a colour PFM')
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype='<f4' if scale < 0 else '>f4')
    return data.reshape(h, w, 3).astype(np.float64)


def main(argv):
    opts = {'--fovea': 'build/release/tools/fovea/fovea', '--scene': 'cornell-translucent', '--eye-size': '96x96',
            '--frames': '5', '--reps': '2', '--out': 'out/sss_bench'}
    cfgs = []
    i = 0
    while i < len(argv):
        if argv[i] in opts and i + 1 < len(argv):
            opts[argv[i]] = argv[i + 1]
            i += 2
        elif '=' in argv[i] and not argv[i].startswith('-'):
            name, args = argv[i].split('=', 1)
            cfgs.append((name, args.split()))
            i += 1
        else:
            raise SystemExit(__doc__)
    if len(cfgs) < 2:
        raise SystemExit(__doc__)
    times = {n: [] for n, _ in cfgs}
    imgs = {}
    for _ in range(int(opts['--reps'])):
        for name, args in cfgs:
            out = os.path.join(opts['--out'], name)
            subprocess.run(['rm', '-rf', out], check=True)
            cmd = [opts['--fovea'], 'run', '--scene', opts['--scene'], '--eye-size', opts['--eye-size'], '--frames',
                   opts['--frames'], '--json', '--view', 'sss', '--float', '--out', out, '--set', 'gi.enabled=off',
                   '--set', 'distort.enabled=off'] + args
            p = subprocess.run(cmd, capture_output=True, text=True)
            if p.returncode:
                raise SystemExit(f'{" ".join(cmd)}: exit {p.returncode}\n{p.stderr}')
            j = json.loads(p.stdout)
            if j['validation_messages']:
                raise SystemExit(f'{name}: {j["validation_messages"]} validation messages')
            ms = {q['name']: q['gpu_ms_median'] for q in j['passes']}
            times[name].append(ms.get('sss', 0.0) + ms.get('shade', 0.0))
            last = sorted(f for f in os.listdir(out) if f.endswith('.pfm'))[-1]
            img = pfm(os.path.join(out, last))
            if not np.isfinite(img).all():
                raise SystemExit(f'{name}: NaN or Inf in {last}')
            imgs.setdefault(name, img)
    ref = cfgs[0][0]
    e = imgs[ref]
    t0 = statistics.median(times[ref])
    print(f'{opts["--scene"]}, {opts["--eye-size"]} per eye, {opts["--frames"]} frames x {opts["--reps"]} runs; '
          f'subsurface pixels: {int((e.sum(axis=2) > 0).sum())}')
    print('| config | settings | sss + shade ms (runs) | speed-up vs ' + ref + ' | mean rel. error |')
    print('| --- | --- | --- | --- | --- |')
    for name, args in cfgs:
        t = statistics.median(times[name])
        rel = np.abs(imgs[name] - e).sum() / e.sum() if e.sum() > 0 else float('nan')
        runs = ', '.join(f'{x:.0f}' for x in times[name])
        sets = ' '.join(a for a in args if a != '--set') or 'balanced'
        print(f'| {name} | {sets} | {t:.1f} ({runs}) | {t0 / t:.1f}x | {100 * rel:.3f}% |')


if __name__ == '__main__':
    main(sys.argv[1:])
