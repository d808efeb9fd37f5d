"""Seed corpus of the filters' differential fuzzer (FilterDifferentialFuzzer.cxx).

  python3 tests/fuzz/make_filter_corpus.py tests/fuzz/corpus_filters
      writes the seeds
  python3 tests/fuzz/make_filter_corpus.py --check <canopy_filters_fuzzer> tests/fuzz/corpus_filters
      checks that the corpus holds exactly what this script writes and that the fuzzer
      runs every seed through all its checks, decoded as the seed's description says
      (a seed the node budget rejects would test nothing). Other files (regression_*:
      inputs that once found a bug) are only run.

The byte format is described at the top of FilterDifferentialFuzzer.cxx. Each seed is
one forest, one camera and one selection; together they cover 1D, 2D (each plane) and
3D, binary and ternary trees, masks, roots without trees, dyadic and irregular
coordinates, 2 to 4 ranks, parallel and perspective views (along an axis, oblique,
inside the domain, pixel-sized cells) and every selection mode and source.
"""
import os

import corpus_check

ORIGINS = [0.0, -3.5, 7.25, 1024.0, -20.5, 0.5, 1048576.0, -96.0]
LOCATIONS, IDS, VALUE_RANGE, BOX, FRUSTUM = range(5)
CAMERA_PLANES, CAMERA_CORNERS, AXIS_PLANES, RANDOM_PLANES = range(4)


def byte(x):
    return max(0, min(255, int(round(x))))


def forest(dim=3, bf=2, axis=2, depth_first=False, dyadic=True, holes=False, roots=(2, 2, 2),
           levels=3, refine=0.5, mask=0.0, seed=1, ranks=1, origin=0):
    """refine: 0.15 to 0.65; mask: 0 (none) to 0.3; origin: an index into ORIGINS."""
    shape = {1: 1, 2: 2, 3: 0}[dim] | int(bf == 3) << 2 | axis << 3 | int(depth_first) << 5 | \
        int(dyadic) << 6 | int(holes) << 7
    out = [shape, (roots[0] - 1) + 3 * (roots[1] - 1) + 9 * (roots[2] - 1), levels - 1,
           byte((refine - 0.15) / 0.5 * 255), 0 if mask == 0 else byte(97 + mask * 530)]
    out += [seed >> 24 & 255, seed >> 16 & 255, seed >> 8 & 255, seed & 255]
    out += [ranks - 1, origin]
    return out


def camera(parallel=True, along=None, focal=(0.5, 0.5, 0.5), azimuth=0.3, elevation=0.6,
           distance=0.5, up=0.2, scale=0.5, viewport=0, threshold=0, properties=False):
    """along: (axis, sign) for a view along an axis; fractions in [0, 1] for the rest
    (focal: of the domain's bounds, -0.25 to 1.25 of them over the byte's range)."""
    flags = int(parallel) | int(not properties) << 5
    if along is not None:
        flags |= 2 | along[0] << 2 | int(along[1] < 0) << 4
    out = [flags] + [byte((f + 0.25) / 1.5 * 255) for f in focal]
    out += [byte(azimuth * 255), byte(elevation * 255), byte(distance * 255), byte(up * 255),
            byte(scale * 255), viewport, threshold]
    return out


def selection(mode, invert=False, allow_masked=False, via_selection=False, inverse=False,
              indices=False):
    return [mode | int(invert) << 3 | int(allow_masked) << 4 | int(via_selection) << 5 |
            int(inverse) << 6 | int(indices) << 7]


def locations(points):
    """points: (kind, pick, detail) each; kinds: 0 centre, 1 lower corner, 2 upper corner,
    3 faces and edges, 4 domain's upper side, 5 outside, 6 lattice, 7 off a flat axis."""
    out = [len(points) - 1]
    for p in points:
        out += [x & 255 for x in p]
    return out


def ids(values):
    out = [len(values) - 1]
    for v in values:
        out += [v >> 8 & 255, v & 255]
    return out


def value_range(field, component=0, low=(False, 0.3), high=(False, 0.7)):
    """field: node, hash or pair (component -1: magnitude); each bound: (exact, x) where
    exact means node x's own value, else x is a fraction of the field's range."""
    f = {"node": 0, "hash": 1, "pair": 2}[field] + 3 * (component + 1 if field == "pair" else 0)
    out = [f]
    for exact, x in (low, high):
        w = 0x8000 | x if exact else int(round((x + 0.1) / 1.2 * 32767))
        out += [w >> 8 & 255, w & 255]
    return out


def box(bounds):
    """Per axis two bounds: ('leaf', pick, upper), ('inf', sign) or a fraction f of the
    domain (from -0.2 to 1.2 of it)."""
    out = []
    for b in bounds:
        if isinstance(b, tuple) and b[0] == "leaf":
            out.append(0x80 | (b[1] & 0x3F) | int(b[2]) << 6)
        elif isinstance(b, tuple):
            out.append(0x7F if b[1] < 0 else 0xFF)
        else:
            out.append(byte((b + 0.2) / 1.4 * 126))
    return out


def frustum(source, near=0.4, far=1.5, aspect=0.5, planes=()):
    """near: 0.02 to 0.95 of the camera's distance, far: 1.02 to 3.02 of it."""
    return [source, byte((near - 0.02) / 0.93 * 255), byte((far - 1.02) / 2.0 * 255),
            byte((aspect - 0.5) / 1.5 * 255)] + list(planes)


def seeds():
    """name -> (bytes, substrings the fuzzer's description of it must contain)."""
    s = {}

    def add(name, f, c, sel, *expect):
        s[name] = (bytes(f + c + sel), list(expect))

    # 3D.
    add("3d_binary_masked_full_box_on_leaf_bounds",
        forest(roots=(3, 2, 2), levels=4, mask=0.15, seed=7),
        camera(parallel=True, azimuth=0.13, elevation=0.62, distance=0.8, scale=0.7),
        selection(BOX) + box([("leaf", 5, 0), ("leaf", 5, 1), ("leaf", 5, 0), ("leaf", 5, 1),
                              ("leaf", 5, 0), ("leaf", 5, 1)]),
        "3D", "branch factor 2", "mask 0.", "box")
    add("3d_zero_thickness_box_on_a_leaf_face_inverted",
        forest(roots=(2, 1, 2), levels=3, refine=0.55, mask=0.1, seed=127),
        camera(parallel=True, azimuth=0.2, elevation=0.7, distance=0.6, scale=0.5),
        selection(BOX, invert=True, allow_masked=True) +
        box([-0.1, 1.1, 0.2, 0.6, ("leaf", 6, 1), ("leaf", 6, 1)]),
        "3D", "box", "inverted")
    add("3d_ternary_perspective_frustum_planes",
        forest(bf=3, roots=(2, 2, 2), levels=3, refine=0.4, seed=11, dyadic=False),
        camera(parallel=False, azimuth=0.4, elevation=0.7, distance=0.6, scale=0.3,
               viewport=1),
        selection(FRUSTUM) + frustum(CAMERA_PLANES, near=0.5, far=1.3, aspect=1.2),
        "3D", "branch factor 3", "perspective", "frustum")
    add("3d_camera_inside_the_domain_lod",
        forest(roots=(2, 2, 2), levels=4, refine=0.5, mask=0.1, seed=21),
        camera(parallel=False, distance=0.02, scale=0.5, viewport=2, threshold=1),
        selection(LOCATIONS) + locations([(0, i * 7, i) for i in range(12)]),
        "3D", "perspective", "locations")
    add("3d_pixel_sized_cells_lod_along_z",
        forest(roots=(2, 2, 2), levels=4, refine=0.65, seed=3),
        camera(parallel=True, along=(2, -1), focal=(0.5, 0.5, 0.5), distance=0.9, scale=0.45,
               viewport=3, threshold=0),
        selection(IDS) + ids([0, 1, 5, 9, 9, 40, 63, 200, 1000, 65535]),
        "3D", "parallel", "ids")
    add("3d_holes_and_masked_selection_allowed_inverted",
        forest(roots=(3, 2, 2), levels=3, mask=0.25, holes=True, seed=5, origin=1),
        camera(parallel=True, azimuth=0.8, elevation=0.3, distance=0.7, scale=0.4),
        selection(LOCATIONS, invert=True, allow_masked=True) +
        locations([(k, 3 * k + 1, 0x1B) for k in range(8)] * 2),
        "3D", "without a tree", "inverted", "masked cells allowed")
    add("3d_value_range_magnitude_exact_bounds",
        forest(roots=(2, 2, 1), levels=4, mask=0.1, seed=13, depth_first=True),
        camera(parallel=False, azimuth=0.55, elevation=0.55, distance=0.9, scale=0.4),
        selection(VALUE_RANGE) + value_range("pair", -1, (True, 17), (False, 0.8)),
        "3D", "depth-first", "value range of pair component -1")
    add("3d_frustum_by_corners_far_origin",
        forest(roots=(2, 1, 2), levels=4, seed=17, origin=6),
        camera(parallel=True, azimuth=0.1, elevation=0.8, distance=0.5, scale=0.35),
        selection(FRUSTUM) + frustum(CAMERA_CORNERS, near=0.3, far=1.6, aspect=0.9),
        "3D", "1048576", "by corners")
    add("3d_six_axis_planes_through_leaf_bounds",
        forest(roots=(2, 2, 2), levels=3, refine=0.6, seed=23),
        camera(),
        selection(FRUSTUM) + frustum(AXIS_PLANES, planes=box(
            [("leaf", 2, 0), ("leaf", 9, 1), ("leaf", 2, 0), ("leaf", 9, 1), 0.1, 0.9])),
        "3D", "six axis-aligned planes")
    add("3d_random_planes_irregular",
        forest(bf=3, roots=(1, 2, 2), levels=3, refine=0.35, seed=29, dyadic=False, origin=3),
        camera(parallel=False, properties=True, distance=0.3, scale=0.6, viewport=5),
        selection(FRUSTUM) + frustum(RANDOM_PLANES, planes=[31 * i % 256 for i in range(18)]),
        "3D", "six random planes", "camera properties")
    add("3d_split_3_ranks_box",
        forest(roots=(2, 2, 2), levels=4, refine=0.55, seed=31, ranks=3),
        camera(parallel=True, azimuth=0.3, elevation=0.4, distance=0.6, scale=0.3),
        selection(BOX) + box([0.2, 0.7, 0.1, 0.6, ("inf", -1), 0.5]),
        "3D", "3 rank(s)", "box")
    add("3d_split_4_ranks_frustum_selection_inverse",
        forest(bf=3, roots=(2, 1, 2), levels=3, refine=0.4, seed=37, ranks=4),
        camera(parallel=False, azimuth=0.7, elevation=0.35, distance=0.7, scale=0.4),
        selection(FRUSTUM, via_selection=True, inverse=True) +
        frustum(CAMERA_PLANES, near=0.4, far=1.8),
        "3D", "4 rank(s)", "a vtkSelection with INVERSE")
    add("3d_split_2_ranks_value_range_hash",
        forest(roots=(3, 1, 1), levels=4, refine=0.6, seed=41, ranks=2, depth_first=True),
        camera(parallel=True, along=(0, 1), scale=0.6, viewport=6, threshold=2),
        selection(VALUE_RANGE, invert=True) + value_range("hash", 0, (False, 0.2), (False, 0.6)),
        "3D", "2 rank(s)", "value range of hash")
    add("3d_split_2_ranks_masked_locations",
        forest(roots=(2, 2, 1), levels=4, refine=0.6, mask=0.15, seed=109, ranks=2),
        camera(parallel=False, azimuth=0.45, elevation=0.6, distance=0.8, scale=0.35),
        selection(LOCATIONS, allow_masked=True) + locations([(k % 7, 9 * k, k) for k in range(20)]),
        "3D", "2 rank(s)", "mask 0.1", "masked cells allowed")
    add("3d_binary_deep_single_root_ids_selection",
        forest(roots=(1, 1, 1), levels=4, refine=0.65, mask=0.2, seed=43),
        camera(parallel=True, azimuth=0.25, elevation=0.75, distance=0.5, scale=0.25,
               viewport=7),
        selection(IDS, via_selection=True, indices=True, allow_masked=True) +
        ids([0, 1, 2, 3, 8, 9, 10, 11, 64, 65, 66, 100, 101, 300]),
        "3D", "ids (INDICES)")

    # 2D, each plane.
    add("2d_xy_binary_axis_view_lod_locations_on_corners",
        forest(dim=2, axis=2, roots=(3, 2, 1), levels=6, refine=0.55, mask=0.1, seed=47),
        camera(parallel=True, along=(2, -1), focal=(0.5, 0.5, 0.0), distance=0.5, scale=0.5,
               viewport=3, threshold=0),
        selection(LOCATIONS) + locations([(3, i * 5, i * 37 % 64) for i in range(20)]),
        "2D normal to z", "locations")
    add("2d_xz_ternary_perspective_frustum_corners",
        forest(dim=2, bf=3, axis=1, roots=(3, 1, 3), levels=4, refine=0.45, seed=53,
               dyadic=False),
        camera(parallel=False, azimuth=0.25, elevation=0.15, distance=0.8, scale=0.35,
               viewport=4),
        selection(FRUSTUM) + frustum(CAMERA_CORNERS, near=0.2, far=2.5),
        "2D normal to y", "branch factor 3", "by corners")
    add("2d_yz_box_with_flat_axis_range_away",
        forest(dim=2, axis=0, roots=(1, 3, 3), levels=5, mask=0.15, seed=59, origin=2),
        camera(parallel=True, along=(0, 1), scale=0.6, viewport=1),
        selection(BOX) + box([1.1, 1.15, ("leaf", 3, 0), ("leaf", 12, 1), 0.3, 0.8]),
        "2D normal to x", "box")
    add("2d_tilted_view_lod_threshold_8",
        forest(dim=2, roots=(3, 3, 1), levels=6, refine=0.6, seed=61, origin=4),
        camera(parallel=False, azimuth=0.6, elevation=0.2, distance=0.6, scale=0.5,
               viewport=2, threshold=2),
        selection(VALUE_RANGE) + value_range("node", 0, (True, 30), (False, 0.9)),
        "2D", "threshold 8", "value range of node")
    add("2d_holes_ids_duplicates_out_of_range",
        forest(dim=2, bf=3, roots=(3, 2, 1), levels=3, refine=0.5, holes=True, seed=67),
        camera(parallel=True, scale=0.9, properties=True),
        selection(IDS) + ids([0, 0, 1, 1, 2, 65535, 65534, 4, 8, 15, 16, 23, 42]),
        "2D", "without a tree", "ids")
    add("2d_split_4_ranks_lod",
        forest(dim=2, roots=(3, 3, 1), levels=6, refine=0.6, seed=71, ranks=4),
        camera(parallel=True, along=(2, -1), focal=(0.5, 0.5, 0.0), distance=0.5, scale=0.4,
               viewport=2, threshold=1),
        selection(LOCATIONS) + locations([(0, i * 11, 0) for i in range(16)]),
        "2D", "4 rank(s)", "locations")
    add("2d_split_3_ranks_frustum_random_planes",
        forest(dim=2, axis=1, bf=3, roots=(3, 1, 2), levels=4, refine=0.5, seed=73, ranks=3,
               dyadic=False),
        camera(parallel=False, azimuth=0.3, elevation=0.3, distance=0.4, scale=0.5),
        selection(FRUSTUM) + frustum(RANDOM_PLANES, planes=[57 * i % 256 for i in range(18)]),
        "2D", "3 rank(s)", "six random planes")
    add("2d_split_3_ranks_masked_box_inverted",
        forest(dim=2, axis=0, roots=(1, 3, 2), levels=5, refine=0.6, mask=0.12, seed=113,
               ranks=3),
        camera(parallel=True, along=(0, -1), scale=0.45, viewport=7, threshold=1),
        selection(BOX, invert=True) + box([0.0, 1.0, 0.25, 0.75, ("leaf", 4, 0), ("leaf", 40, 1)]),
        "2D", "3 rank(s)", "mask 0.1", "inverted")
    add("2d_masked_preserve_allow_masked_value_pair",
        forest(dim=2, roots=(2, 2, 1), levels=5, refine=0.6, mask=0.3, seed=79),
        camera(parallel=True, scale=0.3, viewport=7, threshold=3),
        selection(VALUE_RANGE, allow_masked=True, via_selection=True) +
        value_range("pair", 0, (False, 0.0), (False, 1.0)),
        "2D", "masked cells allowed", "a vtkSelection")
    add("2d_edge_on_view",
        forest(dim=2, roots=(2, 3, 1), levels=5, seed=83),
        camera(parallel=False, azimuth=0.0, elevation=0.5, distance=0.7, scale=0.4),
        selection(BOX) + box([("inf", -1), ("inf", 1), ("leaf", 20, 1), ("leaf", 20, 1),
                              0.0, 1.0]),
        "2D", "box")

    # 1D, each axis.
    add("1d_x_binary_lod_locations_on_ends",
        forest(dim=1, axis=0, roots=(3, 1, 1), levels=8, refine=0.6, mask=0.1, seed=89),
        camera(parallel=True, along=(2, -1), focal=(0.5, 0.5, 0.5), scale=0.55, viewport=2),
        selection(LOCATIONS) + locations([(k % 8, 13 * k, k) for k in range(24)]),
        "1D along x", "locations")
    add("1d_y_ternary_perspective_frustum",
        forest(dim=1, axis=1, bf=3, roots=(1, 3, 1), levels=5, refine=0.55, seed=97,
               dyadic=False, origin=5),
        camera(parallel=False, azimuth=0.1, elevation=0.4, distance=0.5, scale=0.4),
        selection(FRUSTUM) + frustum(CAMERA_PLANES, near=0.1, far=1.2),
        "1D along y", "frustum")
    add("1d_z_split_2_ranks_box",
        forest(dim=1, axis=2, roots=(1, 1, 3), levels=7, refine=0.6, seed=101, ranks=2),
        camera(parallel=True, along=(0, 1), scale=0.6, viewport=6, threshold=2),
        selection(BOX) + box([0.0, 1.0, 0.0, 1.0, ("leaf", 7, 0), ("leaf", 30, 1)]),
        "1D along z", "2 rank(s)", "box")
    add("1d_holes_value_range_inverted",
        forest(dim=1, axis=0, roots=(3, 1, 1), levels=6, holes=True, seed=103, origin=7),
        camera(parallel=False, properties=True, distance=0.4, scale=0.2),
        selection(VALUE_RANGE, invert=True) + value_range("hash", 0, (False, 0.4), (False, 0.9)),
        "1D", "without a tree", "inverted")
    add("1d_split_3_ranks_lod_ids",
        forest(dim=1, axis=1, roots=(1, 3, 1), levels=8, refine=0.65, seed=107, ranks=3),
        camera(parallel=True, along=(2, 1), focal=(0.5, 0.5, 0.5), scale=0.5, viewport=2,
               threshold=1),
        selection(IDS) + ids(list(range(0, 60, 3))),
        "1D", "3 rank(s)", "ids")
    return s


def write(directory):
    os.makedirs(directory, exist_ok=True)
    for name, (data, _) in seeds().items():
        with open(os.path.join(directory, name), "wb") as out:
            out.write(data)


def check(fuzzer, directory):
    every = seeds()

    def judge(name, line):
        if line is None or not line.endswith("checked"):
            return "not run through every check"
        missing = [e for e in (every[name][1] if name in every else []) if e not in line]
        return "its description lacks " + ", ".join(missing) if missing else None

    return corpus_check.check(fuzzer, directory, {n: d for n, (d, _) in every.items()},
                              "make_filter_corpus.py", "canopy filters fuzz input:", judge,
                              "every seed checked, as named")


if __name__ == "__main__":
    corpus_check.main(__doc__, write, check)
