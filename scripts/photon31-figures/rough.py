import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
# Per-pixel RMSE (over the r, g, b values of the pixels) of runs against a reference averaged over seeds,
# on rough.scn's gold sphere (roughness 0.02) and frosted ball (0.15): the pixels whose four corners'
# camera rays all hit that sphere first (the lab camera: origin + forward + a left + b up).
# usage: rough.py 'ref1.ppm ...' NAME file.ppm [NAME file.ppm ...]
import sys, math
from ppm import read, avg
O = (0.0, 0.0, -3.5); L = (-1.0, 0.0, 0.0); U = (0.0, 1.0, 0.0); F = (0.0, 0.0, 3.0)
SPHERES = {'gold 0.02': ((-0.66, -0.2, 0.6), 0.18), 'frosted 0.15': ((-0.55, -0.72, -0.2), 0.28)}
ALL = [((-0.66, -0.2, 0.6), 0.18), ((-0.22, -0.2, 0.6), 0.18), ((0.22, -0.2, 0.6), 0.18),
       ((0.66, -0.2, 0.6), 0.18), ((-0.55, -0.72, -0.2), 0.28), ((0.55, -0.75, -0.25), 0.25)]
def hit(d, c, r):
    oc = [O[i] - c[i] for i in range(3)]
    a = sum(x*x for x in d); b = sum(oc[i]*d[i] for i in range(3)); cc = sum(x*x for x in oc) - r*r
    disc = b*b - a*cc
    return (-b - math.sqrt(disc)) / a if disc >= 0 else None
def first(x, y):  # x, y in [0, 1]
    a, b = 1 - 2*x, 1 - 2*y
    d = [F[i] + a*L[i] + b*U[i] for i in range(3)]
    ts = [(hit(d, c, r), (c, r)) for c, r in ALL]
    ts = [t for t in ts if t[0] is not None and t[0] > 0]
    return min(ts)[1] if ts else None
def mask(w, h, sphere):
    return [(x, y) for y in range(h) for x in range(w)
            if all(first((x+dx)/w, (y+dy)/h) == sphere for dx in (0, 1) for dy in (0, 1))]
refs = [read(p) for p in sys.argv[1].split()]
ref = avg(refs)
w, h, rv = ref
masks = {n: mask(w, h, s) for n, s in SPHERES.items()}
n = len(refs)
def rmse(v, px):
    return math.sqrt(sum((v[y*w+x][c] - rv[y*w+x][c])**2 for x, y in px for c in range(3)) / (3*len(px)))
def ref_noise(px):  # the reference's own per-pixel standard error (seeds' spread / sqrt n), rms over the mask
    s = 0.0
    for x, y in px:
        for c in range(3):
            vals = [im[2][y*w+x][c] for im in refs]; m = sum(vals)/n
            s += sum((t-m)**2 for t in vals)/(n-1)/n
    return math.sqrt(s / (3*len(px)))
for nm, px in masks.items():
    mref = sum(sum(rv[y*w+x]) / 3 for x, y in px) / len(px)
    print('%s: %d pixels, reference mean %.5f, reference own noise (rms se) %.5f' % (nm, len(px), mref, ref_noise(px)))
for i in range(2, len(sys.argv), 2):
    v = read(sys.argv[i+1])[2]
    row = []
    for nm, px in masks.items():
        m = sum(sum(v[y*w+x]) / 3 for x, y in px) / len(px)
        mref = sum(sum(rv[y*w+x]) / 3 for x, y in px) / len(px)
        row.append('%s RMSE %.4f (mean %+.1f %%)' % (nm, rmse(v, px), 100*(m/mref-1)))
    print('%-28s %s' % (sys.argv[i], ' | '.join(row)))
