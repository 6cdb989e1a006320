# Read raydiance's P3 PPM (with its '#MAX=' comment) into (w, h, [r, g, b per pixel]) in linear radiance.
def read(path):
    toks = []
    mx = None
    for line in open(path):
        if line.startswith('#MAX='):
            mx = float(line[5:]); continue
        if line.startswith('#'):
            continue
        toks += line.split()
    assert toks[0] == 'P3' and mx is not None
    w, h, res = int(toks[1]), int(toks[2]), int(toks[3])
    v = [float(t) / res * mx for t in toks[4:]]
    return w, h, [(v[3*i], v[3*i+1], v[3*i+2]) for i in range(w*h)]

def avg(imgs):
    w, h = imgs[0][0], imgs[0][1]
    n = len(imgs)
    return w, h, [tuple(sum(im[2][i][c] for im in imgs) / n for c in range(3)) for i in range(w*h)]

def mean_se(xs):
    n = len(xs)
    m = sum(xs) / n
    if n < 2:
        return m, float('nan')
    var = sum((x - m) ** 2 for x in xs) / (n - 1)
    return m, (var / n) ** 0.5
