#!/usr/bin/env python3
"""Reads outlinefit's DXF and GeoJSON back with independent libraries and checks them.

    check_exports.py dxf FILE REPORT.json VERSION INSUNITS PER_PIXEL
    check_exports.py geojson FILE

`dxf` reads the drawing with ezdxf and checks: the DXF version (AC1015 for R2000, AC1009
for R12), $INSUNITS, that every entity is in the layer `outline`, that the drawing
audits clean, and that every loop is closed. For R2000 it checks each SPLINE against
the report's curves: degree 3, rational, knots 0 0 0 0 1 1 1 … n n n n, control points
and weights those of the fitted segments (y flipped, times PER_PIXEL), and the spline
evaluated by ezdxf at 17 points of every span within 1e-9 of the rational cubic
evaluated here from the report. It prints {"loops": [[[x, y], …], …]} (each loop
flattened within 1e-4 units by ezdxf) for the caller to rasterise.

`geojson` checks the document with shapely: a FeatureCollection of Polygon features,
every polygon valid, outer rings counter-clockwise and holes clockwise (RFC 7946), and
prints {"areas": […]}.

Exit status: 0 checked, 1 a check failed (the message says which), 3 ezdxf or shapely
is missing (the caller skips).
"""

import json
import sys

try:
    import ezdxf
    from ezdxf.math import BSpline, Vec3
    import shapely.geometry
    import shapely.validation
except ImportError as e:  # pragma: no cover - depends on the machine
    print(f"missing Python module: {e.name}", file=sys.stderr)
    sys.exit(3)


def fail(message):
    print(message, file=sys.stderr)
    sys.exit(1)


def rational_cubic(points, weights, t):
    """The rational cubic Bézier curve at t, evaluated from its definition."""
    s = 1.0 - t
    basis = [s * s * s, 3 * s * s * t, 3 * s * t * t, t * t * t]
    wb = [b * w for b, w in zip(basis, weights)]
    total = sum(wb)
    return (
        sum(c * p[0] for c, p in zip(wb, points)) / total,
        sum(c * p[1] for c, p in zip(wb, points)) / total,
    )


def check_dxf(path, report_path, version, insunits, per_pixel):
    doc = ezdxf.readfile(path)
    if doc.dxfversion != version:
        fail(f"DXF version {doc.dxfversion}, expected {version}")
    if doc.header.get("$INSUNITS", 0) != insunits:
        fail(f"$INSUNITS {doc.header.get('$INSUNITS')}, expected {insunits}")
    if "outline" not in doc.layers:
        fail("no layer named outline")
    auditor = doc.audit()
    if auditor.has_errors:
        fail(f"audit errors: {[str(e.message) for e in auditor.errors]}")
    entities = list(doc.modelspace())
    for e in entities:
        if e.dxf.layer != "outline":
            fail(f"{e.dxftype()} in layer {e.dxf.layer}")
    report = json.load(open(report_path))
    image = report["images"][0]
    height = image["image"]["height"]
    contours = [c for c in image["contours"] if c["segments"]]
    if len(entities) != len(contours):
        fail(f"{len(entities)} entities for {len(contours)} contours")

    def to_page(p):
        return (p[0] * per_pixel, (height - p[1]) * per_pixel)

    loops = []
    worst = 0.0
    for entity, contour in zip(entities, contours):
        if version == "AC1009":
            if entity.dxftype() != "POLYLINE" or not entity.is_closed:
                fail(f"{entity.dxftype()} is not a closed POLYLINE")
            loops.append([[v.dxf.location.x, v.dxf.location.y] for v in entity.vertices])
            continue
        if entity.dxftype() != "SPLINE":
            fail(f"{entity.dxftype()} where a SPLINE was expected")
        segments = contour["segments"]
        n = len(segments)
        if entity.dxf.degree != 3:
            fail(f"spline of degree {entity.dxf.degree}")
        if not entity.dxf.flags & 4:
            fail("spline not marked rational")
        knots = list(entity.knots)
        expected = [0.0] * 4 + [float(k) for k in range(1, n) for _ in range(3)] + [float(n)] * 4
        if knots != expected:
            fail(f"knots {knots[:10]}…, expected {expected[:10]}…")
        cps = [tuple(p)[:2] for p in entity.control_points]
        weights = list(entity.weights)
        if len(cps) != 3 * n + 1 or len(weights) != 3 * n + 1:
            fail(f"{len(cps)} control points, {len(weights)} weights for {n} segments")
        if cps[0] != cps[-1]:
            fail(f"open loop: {cps[0]} to {cps[-1]}")
        curve = BSpline(
            [Vec3(x, y, 0) for x, y in cps], order=4, knots=knots, weights=weights
        )
        for k, seg in enumerate(segments):
            points = [to_page(p) for p in seg["control_points"]]
            for j in range(17):
                t = j / 16
                want = rational_cubic(points, seg["weights"], t)
                got = curve.point(k + t)
                worst = max(worst, abs(got.x - want[0]), abs(got.y - want[1]))
        loops.append([[p.x, p.y] for p in curve.flattening(1e-4, segments=8)])
    if worst > 1e-9:
        fail(f"a spline is {worst:.3g} units from the report's curve (limit 1e-9)")
    for loop in loops:
        if len(loop) < 3:
            fail("a loop of fewer than three points")
    json.dump({"loops": loops, "max_spline_error": worst}, sys.stdout)


def check_geojson(path):
    doc = json.load(open(path))
    if doc.get("type") != "FeatureCollection":
        fail(f"type {doc.get('type')}, expected FeatureCollection")
    areas = []
    for feature in doc["features"]:
        if feature.get("type") != "Feature":
            fail("a member of features is not a Feature")
        geometry = feature["geometry"]
        if geometry["type"] != "Polygon":
            fail(f"geometry {geometry['type']}, expected Polygon")
        for ring in geometry["coordinates"]:
            if ring[0] != ring[-1] or len(ring) < 4:
                fail("a ring that is not closed")
        polygon = shapely.geometry.shape(geometry)
        if not polygon.is_valid:
            fail(f"invalid polygon: {shapely.validation.explain_validity(polygon)}")
        if not polygon.exterior.is_ccw:
            fail("an outer ring turns clockwise (RFC 7946 asks counter-clockwise)")
        for hole in polygon.interiors:
            if hole.is_ccw:
                fail("a hole turns counter-clockwise (RFC 7946 asks clockwise)")
        areas.append(polygon.area)
    json.dump({"areas": areas}, sys.stdout)


def main():
    if len(sys.argv) >= 2 and sys.argv[1] == "dxf" and len(sys.argv) == 7:
        check_dxf(sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5]), float(sys.argv[6]))
    elif len(sys.argv) == 3 and sys.argv[1] == "geojson":
        check_geojson(sys.argv[2])
    else:
        fail(__doc__)


if __name__ == "__main__":
    main()
