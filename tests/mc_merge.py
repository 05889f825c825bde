#!/usr/bin/env python3
"""mc_merge.py - merges two tables of tests/mc_sea_oracle.c -f means drawn
over disjoint seeds of the same surfaces (the same -n, -d, -r, wavelengths
and directions; period_m, where the tables have it, must agree), so that a
table can take more surfaces without tracing its first ones again:

    tests/mc_merge.py A.csv NA B.csv NB OUT.csv

A's comment lines, header and rows are kept, in A's order; each row of A
whose (wind, wavelength, theta, phi) B also has becomes the mean over the
NA + NB surfaces: sxx, syy, sxy and multi weighted by surfaces; eps1 and
eps with their standard errors from the pooled sums of squares (each _se is
the sample deviation over its surfaces, n - 1, divided by sqrt(n)), as one
run over all NA + NB surfaces would give them.  The model columns are left
as A's: tests/mc_model_refresh recomputes them at the new covariances.
Python's standard library only."""
import math
import sys


def read(path):
    comments, header, rows = [], None, []
    with open(path) as f:
        for line in f:
            if line.startswith('#'):
                comments.append(line)
            elif header is None:
                header = line.strip().split(',')
            elif line.strip():
                rows.append(line.strip().split(','))
    return comments, header, rows


def main():
    if len(sys.argv) != 6:
        sys.exit('usage: mc_merge.py A.csv NA B.csv NB OUT.csv')
    na, nb = int(sys.argv[2]), int(sys.argv[4])
    if na < 2 or nb < 2:
        sys.exit('mc_merge.py: each table needs at least 2 surfaces')
    comments, header, rows_a = read(sys.argv[1])
    _, header_b, rows_b = read(sys.argv[3])
    if header != header_b:
        sys.exit('mc_merge.py: the two tables have different columns')
    col = {name: i for i, name in enumerate(header)}
    n = na + nb
    by_key = {tuple(r[:4]): r for r in rows_b}

    def pooled(ma, sa, mb, sb):
        va, vb = sa * sa * na, sb * sb * nb  # sample variances
        mean = (na * ma + nb * mb) / n
        ss = (na - 1) * va + (nb - 1) * vb + na * nb / n * (ma - mb) ** 2
        return mean, math.sqrt(ss / (n - 1) / n)

    out = []
    for a in rows_a:
        b = by_key.get(tuple(a[:4]))
        if b is None:
            out.append(a)
            continue
        if 'period_m' in col and a[col['period_m']] != b[col['period_m']]:
            sys.exit('mc_merge.py: wind %s: surfaces of periods %s and %s m are not one draw'
                     % (a[0], a[col['period_m']], b[col['period_m']]))
        m = list(a)
        for name in ('sxx', 'syy', 'sxy', 'multi'):
            v = (na * float(a[col[name]]) + nb * float(b[col[name]])) / n
            m[col[name]] = ('%.4f' if name == 'multi' else '%.10g') % v
        for name in ('eps1', 'eps'):
            mean, se = pooled(float(a[col[name]]), float(a[col[name + '_se']]),
                              float(b[col[name]]), float(b[col[name + '_se']]))
            m[col[name]] = '%.6f' % mean
            m[col[name + '_se']] = '%.6f' % se
        out.append(m)
    with open(sys.argv[5], 'w') as f:
        f.writelines(comments)
        f.write(','.join(header) + '\n')
        for r in out:
            f.write(','.join(r) + '\n')


if __name__ == '__main__':
    main()
