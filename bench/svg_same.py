#!/usr/bin/env python3
"""Tell whether two SVG files (or two folders of them) hold the same document.

Same document: the same elements in the same order, each with the same attributes and the
same text; the order of attributes and the whitespace between elements do not count. With
--tolerance T, numbers inside attribute values may differ by up to T (for pictures whose
number format changed); otherwise values must be equal strings.

    python3 bench/svg_same.py OLD NEW [--tolerance 0.005]

Prints one line per differing file and a summary; exits 1 if any differ.
"""

import argparse
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

NUMBER = re.compile(r"-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def same_value(a, b, tolerance):
    if a == b:
        return True
    if tolerance is None:
        return False
    na, nb = NUMBER.findall(a), NUMBER.findall(b)
    if NUMBER.sub("#", a) != NUMBER.sub("#", b) or len(na) != len(nb):
        return False
    return all(abs(float(x) - float(y)) <= tolerance for x, y in zip(na, nb))


def compare(a, b, tolerance, where="/"):
    here = f"{where}{a.tag.split('}')[-1]}"
    if a.tag != b.tag:
        return f"{here}: element {b.tag} instead of {a.tag}"
    if set(a.attrib) != set(b.attrib):
        return f"{here}: attributes {sorted(a.attrib)} vs {sorted(b.attrib)}"
    for k in a.attrib:
        if not same_value(a.attrib[k], b.attrib[k], tolerance):
            return f"{here}@{k}: {a.attrib[k][:80]!r} vs {b.attrib[k][:80]!r}"
    if (a.text or "").strip() != (b.text or "").strip():
        return f"{here}: text {a.text!r} vs {b.text!r}"
    ca, cb = list(a), list(b)
    if len(ca) != len(cb):
        return f"{here}: {len(ca)} children vs {len(cb)}"
    for i, (x, y) in enumerate(zip(ca, cb)):
        d = compare(x, y, tolerance, f"{here}[{i}]/")
        if d:
            return d
    return None


def comments(path):
    return re.findall(r"<!--(.*?)-->", path.read_text(), re.S)


def check(old, new, tolerance):
    try:
        d = compare(ET.parse(old).getroot(), ET.parse(new).getroot(), tolerance)
    except ET.ParseError as e:
        return f"does not parse: {e}"
    if d is None and comments(old) != comments(new):
        d = "comments differ"
    return d


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--tolerance", type=float, default=None)
    args = ap.parse_args()
    if args.old.is_dir():
        pairs = [(p, args.new / p.relative_to(args.old)) for p in sorted(args.old.rglob("*.svg"))]
    else:
        pairs = [(args.old, args.new)]
    differ = 0
    for old, new in pairs:
        d = "missing" if not new.exists() else check(old, new, args.tolerance)
        if d:
            differ += 1
            print(f"{new}: {d}")
    print(f"{len(pairs)} files, {len(pairs) - differ} the same document, {differ} differ")
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    main()
