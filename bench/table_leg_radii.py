#!/usr/bin/env python3
"""Per-leg radius of a completed table at the bulb height, for issue 10 (part symmetries).

usage: /usr/bin/python3 bench/table_leg_radii.py MODEL_SAMPLES.ply OUTPUT.ply
MODEL_SAMPLES.ply: `scanfill sample --input procedural:table --count 60000`. Prints, per leg (quadrant), the model's
90th-percentile radius at the widest height and the median radius of the output's points there, per origin
(0 scan, 1 synthesised, 2 copied)."""
import sys

import numpy as np

def readply(p):
    with open(p,'rb') as f:
        props=[];n=0;fmt=None
        while True:
            l=f.readline().decode().strip()
            if l.startswith('format'): fmt=l
            if l.startswith('element vertex'): n=int(l.split()[2])
            if l.startswith('property'): props.append(l.split()[1:])
            if l=='end_header': break
        if 'ascii' in fmt:
            a=np.loadtxt(f,max_rows=n); return {p[-1]:a[:,i] for i,p in enumerate(props)}
        tm={'float':'<f4','uchar':'u1','int':'<i4','double':'<f8','uint':'<u4'}
        dt=np.dtype([(p[-1],tm[p[0]]) for p in props]); a=np.frombuffer(f.read(n*dt.itemsize),dt)
        return {k:a[k] for k in dt.names}
m=readply(sys.argv[1]); o=readply(sys.argv[2])
z=m['z']; top=z.max()
legs=(z<0.5*top)
for sx in (-1,1):
  for sy in (-1,1):
    q=legs&(np.sign(m['x'])==sx)&(np.sign(m['y'])==sy)
    cx,cy=np.median(m['x'][q]),np.median(m['y'][q])
    r=np.hypot(m['x'][q]-cx,m['y'][q]-cy); zq=z[q]
    # bulb height: z bin with max radius
    bins=np.linspace(zq.min(),zq.max(),30); idx=np.digitize(zq,bins)
    rb=[np.percentile(r[idx==i],90) if (idx==i).sum()>5 else 0 for i in range(len(bins)+1)]
    ib=int(np.argmax(rb)); zb=(bins[max(ib-1,0)]+bins[min(ib,len(bins)-1)])/2
    sel=(np.abs(o['z']-zb)<0.02)&(np.hypot(o['x']-cx,o['y']-cy)<0.12)
    ro=np.hypot(o['x'][sel]-cx,o['y'][sel]-cy)
    s=f"leg({sx:+d},{sy:+d}) c=({cx:.2f},{cy:.2f}) bulb z={zb:.3f} model r90={rb[ib]:.3f} plain(min bin r)={min(x for x in rb if x>0):.3f} |"
    for org in np.unique(o['origin'][sel]):
        k=o['origin'][sel]==org
        s+=f" origin{org}: n={k.sum()} r med={np.median(ro[k]):.3f} labels={np.unique(o['label'][sel][k]).tolist()[:5]}"
    print(s)
