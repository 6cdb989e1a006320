import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
# Region means (grey = mean of r, g, b, as /tmp/p31/regions.py) of runs against a reference averaged over seeds.
# usage: outdoor.py REGIONS 'ref1.ppm ref2.ppm ...' NAME 'run1.ppm ...' [NAME 'runs' ...]
import sys
from ppm import read, mean_se
def region(img, r):
    w, h, v = img
    x0, y0, x1, y1 = r
    px = [sum(v[y*w+x]) / 3 for y in range(int(y0*h), int(y1*h)) for x in range(int(x0*w), int(x1*w))]
    return sum(px) / len(px)
regions = eval(open(sys.argv[1]).read())
w0 = read(sys.argv[2].split()[0])
regions.append(('image mean', (0, 0, 1, 1)))
refs = [read(p) for p in sys.argv[2].split()]
runs = [(sys.argv[i], [read(p) for p in sys.argv[i+1].split()]) for i in range(3, len(sys.argv), 2)]
print('%-22s %-22s' % ('region', 'path (mean +- se)') + ''.join('%-26s' % ('%s (%d)' % (n, len(r))) for n, r in runs))
for name, r in regions:
    m, se = mean_se([region(im, r) for im in refs])
    row = '%-22s %9.5f +- %-9.5f' % (name, m, se)
    for n, imgs in runs:
        rm, rse = mean_se([region(im, r) for im in imgs])
        d = 100 * (rm / m - 1)
        # error of the ratio: run's seed spread and path's, combined
        e = 100 * ((rse / m) ** 2 + (rm * se / m**2) ** 2) ** 0.5 if len(imgs) > 1 else 100 * rm * se / m**2
        row += '%+7.2f %% +- %5.2f %%       ' % (d, e)
    print(row)
