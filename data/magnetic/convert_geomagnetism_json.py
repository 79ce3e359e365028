#!/usr/bin/env python3
"""Writes a WMM coefficient file in NOAA's WMM.COF text layout from the JSON of the npm package
`geomagnetism` (data/wmm-*.json; coefficient index n(n+1)/2 + m, as its lib/model.js reads them).

    convert_geomagnetism_json.py wmm-2025.json WMM2025.COF

The COF layout (NOAA's WMM.COF): a header "epoch model-name release-date (MM/DD/YYYY)", one row
"n m g h gdot hdot" per degree n = 1..N and order m = 0..n (nT, nT/yr), then two lines of 9s.
The release date is the package's start_date (the model's release, from which it is valid)."""
import json
import sys


def main(src, dst):
    with open(src) as f:
        d = json.load(f)
    n_max = d["n_max"]
    if d["n_max_sec_var"] != n_max:
        sys.exit(f"{src}: n_max_sec_var {d['n_max_sec_var']} differs from n_max {n_max}")
    keys = ["main_field_coeff_g", "main_field_coeff_h", "secular_var_coeff_g", "secular_var_coeff_h"]
    size = n_max * (n_max + 1) // 2 + n_max + 1
    for k in keys:
        if len(d[k]) != size:
            sys.exit(f"{src}: {k} has {len(d[k])} values, expected {size} for n_max {n_max}")
    released = d["start_date"][:10]  # YYYY-MM-DD
    y, mo, da = released.split("-")
    lines = [f"    {float(d['epoch']):.1f}            {d['name']:<16}{mo}/{da}/{y}"]
    for n in range(1, n_max + 1):
        for m in range(n + 1):
            i = n * (n + 1) // 2 + m
            g, h, gd, hd = (d[k][i] for k in keys)
            lines.append(f"{n:3d}{m:3d}{g:10.1f}{h:10.1f}{gd:11.1f}{hd:11.1f}")
    lines += ["9" * 48, "9" * 48]
    with open(dst, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
