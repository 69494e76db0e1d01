#!/usr/bin/env python3
"""Checks a scored run of the development corpus against the fidelity targets, item by
item, beside potrace scored in the same session.

usage (from the bench folder that holds results/, e.g. ../shared/bench):
    python3 PROJECT/bench/fidelity_targets.py results/outlinefit.csv [results/baseline-potrace.csv]

Prints, per subset: items that failed, items more than 1 px worse in Hausdorff than potrace
on the same item, items above 3 px (ours and potrace's), and the mean ratios of area error
(symmetric difference), Hausdorff distance, segment count and SVG bytes to potrace's; then
the worst items. Exit status 1 when a target is missed:
  - no item fails, none is more than 1 px worse than potrace, the count above 3 px is at
    most a third of potrace's (rounded down, at least 0);
  - anti-aliased glyphs (dev-glyph64/256, dev-more64/256): area <= 0.4x, Hausdorff <= 0.6x,
    segments <= 1x potrace; the other subsets <= 1x on all three;
  - SVG bytes <= 1x potrace's on every subset (the speed issue's size target).
"""
import csv
import sys
from collections import defaultdict

ours_path = sys.argv[1]
base_path = sys.argv[2] if len(sys.argv) > 2 else "results/baseline-potrace.csv"


def load(path):
    with open(path, newline="") as f:
        return {r["id"]: r for r in csv.DictReader(f)}


ours, base = load(ours_path), load(base_path)
by_subset = defaultdict(list)
for item, b in base.items():
    by_subset[b["subset"]].append(item)

ANTI_ALIASED = {"dev-glyph64", "dev-glyph256", "dev-more64", "dev-more256"}
missed = []
worse_items = []
print("| subset | items | failed | >1 px worse than potrace | >3 px ours / potrace | area ratio | Hausdorff ratio | segments ratio | bytes ratio |")
print("|---|---|---|---|---|---|---|---|---|")
for subset in sorted(by_subset):
    ids = by_subset[subset]
    failed = [i for i in ids if ours.get(i, {}).get("status") != "ok"]
    ok = [i for i in ids if i not in failed]
    worse = [i for i in ok if float(ours[i]["hausdorff_px"]) > float(base[i]["hausdorff_px"]) + 1.0]
    worse_items += [(float(ours[i]["hausdorff_px"]) - float(base[i]["hausdorff_px"]), i) for i in worse]
    above = sum(float(ours[i]["hausdorff_px"]) > 3 for i in ok)
    above_base = sum(float(base[i]["hausdorff_px"]) > 3 for i in ids)

    def ratio(col):
        a = sum(float(ours[i][col]) for i in ok) / max(len(ok), 1)
        b = sum(float(base[i][col]) for i in ok) / max(len(ok), 1)
        return a / b if b else float("nan")

    ra, rh, rs, rb = ratio("symdiff_px"), ratio("hausdorff_px"), ratio("segments"), ratio("bytes")
    print(f"| {subset} | {len(ids)} | {len(failed)} | {len(worse)} | {above} / {above_base} | {ra:.2f} | {rh:.2f} | {rs:.2f} | {rb:.2f} |")
    limits = (0.4, 0.6, 1.0, 1.0) if subset in ANTI_ALIASED else (1.0, 1.0, 1.0, 1.0)
    if failed:
        missed.append(f"{subset}: {len(failed)} failed")
    if worse:
        missed.append(f"{subset}: {len(worse)} items >1 px worse than potrace")
    if above > above_base // 3:
        missed.append(f"{subset}: {above} items above 3 px (potrace {above_base})")
    for name, r, lim in zip(("area", "Hausdorff", "segments", "bytes"), (ra, rh, rs, rb), limits):
        if not r <= lim:
            missed.append(f"{subset}: {name} ratio {r:.2f} > {lim}")

print()
for d, i in sorted(worse_items, reverse=True)[:15]:
    print(f"worse than potrace by {d:.2f} px: {i} (ours {float(ours[i]['hausdorff_px']):.2f}, potrace {float(base[i]['hausdorff_px']):.2f})")
print()
if missed:
    print("targets missed:")
    for m in missed:
        print("  " + m)
    sys.exit(1)
print("all targets met")
