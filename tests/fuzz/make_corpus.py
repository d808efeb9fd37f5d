"""Seed corpus of the forest-description fuzzer (ForestDescriptionFuzzer.cxx).

  python3 tests/fuzz/make_corpus.py tests/fuzz/corpus
      writes the seeds (valid_*: a valid forest; invalid_*: one defect each)
  python3 tests/fuzz/make_corpus.py --check <canopy_forest_fuzzer> tests/fuzz/corpus
      checks that the corpus holds exactly what this script writes, and that the
      fuzzer builds every valid_* input and refuses every invalid_* one. Other files
      (regression_*: inputs that once found a bug) are only run.

The byte format is described at the top of ForestDescriptionFuzzer.cxx; Seed below
writes it field by field, walking each tree as the decoder does to know which nodes
read a byte.
"""
import os

import corpus_check

BUDGET = 1200  # NodeBudget in the fuzzer
WILD_LEVELS = [0, -1, -2**31, 2**31 - 1, 61, 62, 63, 64, 38, 39, 40, 6, 7, 8, 9, 10]
FLOAT32, FLOAT64, INT32, INT64 = range(4)
AOS, SOA, STRIDED, INDIRECT = range(4)
ALL, NONE, SOME, UNKNOWN = range(4)


class Seed:
    def __init__(self, dim3=False, bf3=False, elsewhere=False, slots=False, flat=2,
                 request=ALL, levels=3, levels_byte=None, points=(3, 3, 3), grid_defect=0,
                 spacing=0, line=None):
        """line: a 1D grid along that axis (the flat-axis bits 3, the grid defect's axis)."""
        self.bytes = bytearray()
        if line is not None:
            flat = 3
            grid_defect = grid_defect % 16 + 16 * line
        self.children = (3 if bf3 else 2) ** (1 if line is not None else 3 if dim3 else 2)
        self.slots = slots
        self.request = request
        self.budget = BUDGET
        self.trees = []
        self.fields = []
        self.put(int(dim3) | int(bf3) << 1 | int(elsewhere) << 2 | int(slots) << 3 | flat << 4 |
                 request << 6)
        if levels_byte is None:
            assert 1 <= levels <= 5
            levels_byte = levels - 1
        self.put(levels_byte)
        # Trees may have maxLevels levels; with an invalid maxLevels, roots only.
        levels = levels if levels_byte < 0xF0 else WILD_LEVELS[levels_byte - 0xF0]
        self.cap = levels if 1 <= levels <= (39 if bf3 else 62) else 1
        if line is not None:
            self.points = [p if a == line else 1 for a, p in enumerate(points)]
        else:
            self.points = [1 if not dim3 and a == flat else p for a, p in enumerate(points)]
        for p in points:
            self.put(max(p - 2, 0))
        self.put(grid_defect)
        self.put(spacing)

    def put(self, *values):
        self.bytes.extend(v & 0xFF for v in values)

    def root_cells(self):
        cells = 1
        for p in self.points:
            cells *= max(p - 1, 1)
        return cells

    def tree(self, root_pick=0, refine=(), mask=None, absent=None, defect=0):
        """refine: the decision (True = refined) for each node that may refine, in
        breadth-first order; mask: one bool per node; absent: one per leaf below the root."""
        self.trees.append((root_pick, refine, mask, absent, defect))
        return self

    def field(self, type_=FLOAT64, layout=AOS, leaves_only=False, components=1, padding=0,
              extra=0, special=0, null_when_empty=False, defect=0):
        a = type_ | layout << 2 | int(leaves_only) << 4 | (components - 1) << 5
        b = padding | extra << 2 | special << 4 | int(null_when_empty) << 7
        self.fields.append((a, b, defect))
        return self

    def build(self, slot_seed=1, slot_defect=0, chosen=0):
        self.put(len(self.trees))
        for root_pick, refine, mask, absent, defect in self.trees:
            cap = self.cap + 1 if defect == 52 else self.cap  # BeyondMaxLevels
            self.put(root_pick, int(mask is not None) | int(absent is not None) << 1 | defect << 2)
            levels = [0]
            refined = [False]
            decisions = iter(refine)
            self.budget -= min(self.budget, 1)
            n = 0
            while n < len(levels):
                if levels[n] + 1 < cap and self.budget >= self.children:
                    r = next(decisions, False)
                    self.put(1 if r else 0)
                    if r:
                        refined[n] = True
                        levels += [levels[n] + 1] * self.children
                        refined += [False] * self.children
                        self.budget -= self.children
                n += 1
            if mask is not None:
                assert len(mask) == len(levels), "mask: %d nodes" % len(levels)
                self.put(*[1 if m else 0 for m in mask])
            if absent is not None:
                leaves = [i for i in range(1, len(levels)) if not refined[i]]
                assert len(absent) == len(leaves), "absent: %d leaves below the root" % len(leaves)
                self.put(*[1 if x else 0 for x in absent])
        if self.slots and self.trees:
            self.put(slot_seed >> 24, slot_seed >> 16, slot_seed >> 8, slot_seed, slot_defect)
        self.put(len(self.fields))
        for a, b, defect in self.fields:
            self.put(a, b, defect)
        if self.request >= SOME:
            self.put(chosen)
        return bytes(self.bytes)


def every_layout(seed, leaves_only=False):
    types = [FLOAT32, FLOAT64] if leaves_only else [FLOAT64, FLOAT32, INT32, INT64]
    for layout, type_ in zip([AOS, SOA, STRIDED, INDIRECT], types * 2):
        seed.field(type_, layout, leaves_only, components=1 + layout % 3, padding=1,
                   extra=layout % 2, special=4 + layout if type_ in (FLOAT32, FLOAT64) else 0)
    return seed


def seeds():
    s = {}
    s["valid_2d_single_root"] = Seed(points=(2, 2, 1), levels=1).tree().field().build()
    s["valid_2d_every_layout"] = every_layout(
        Seed(levels=3).tree(0, [True, True, False, False, True])
        .tree(1, [False])).build()
    s["valid_3d_ternary_leaves_only_masked"] = every_layout(
        Seed(dim3=True, bf3=True, levels=2, points=(2, 2, 3))
        .tree(0, [True], mask=[False] * 3 + [True] * 25)
        .tree(0, [True], mask=[False] + [True] * 27), leaves_only=True).build()
    s["valid_absent_parts_with_slots"] = every_layout(
        Seed(slots=True, elsewhere=True, levels=3).tree(0, [True, True, False, False, True])
        .tree(2, [True, False, False, False, False],
              absent=[False, False, True, True]), leaves_only=True).build(slot_seed=12345)
    s["valid_absent_every_node_fields"] = every_layout(
        Seed(levels=3, points=(3, 2, 1)).tree(0, [True, False, True, False, False],
                                              absent=[True, False, True, True, True, False, True])
    ).build()
    s["valid_yz_plane_some_fields"] = every_layout(
        Seed(flat=0, request=SOME, levels=2, points=(1, 4, 3)).tree(3, [True]).tree(1, [False])
    ).build(chosen=0b1010)
    s["valid_3d_binary_max_levels_62"] = Seed(
        dim3=True, levels_byte=0xF5, points=(2, 3, 2)).tree(0, [True, True, False, True]).field(
            INT64, STRIDED, components=3, padding=2).build()
    s["valid_no_trees_null_fields"] = Seed().field(FLOAT64, AOS, null_when_empty=True).field(
        FLOAT32, SOA, components=2, null_when_empty=True).field(
            INT32, INDIRECT, null_when_empty=True).build()
    s["valid_1d_ternary_line_along_y_leaves_only"] = every_layout(
        Seed(bf3=True, line=1, levels=3, points=(3, 4, 2), request=SOME)
        .tree(2, [True, False, True, False], mask=[False] * 4 + [True] + [False] * 2)
        .tree(0, [False]), leaves_only=True).build(chosen=0b0111)
    s["valid_1d_binary_line_along_z_absent"] = every_layout(
        Seed(elsewhere=True, line=2, levels=4, points=(2, 2, 4))
        .tree(1, [True, True, False, True, False], absent=[True, False, False, True])).build()
    s["invalid_1d_grid_with_a_second_axis"] = Seed(line=0, grid_defect=14).tree(0, [True]).build()
    base = lambda: Seed(levels=3).tree(0, [True, False, True, False, False]).tree(1, [True])
    s["invalid_too_few_tuples"] = base().field(FLOAT64, SOA, components=2, defect=18).build()
    s["invalid_duplicate_root"] = Seed(levels=2).tree(0, [True]).tree(0, [False], defect=55).build()
    s["invalid_too_many_points"] = Seed(grid_defect=15 + 16).tree(0, [True]).build()
    s["invalid_refined_absent_node"] = Seed(levels=3).tree(
        0, [True, True], absent=[False] * 7, defect=54).build()
    s["invalid_unknown_field_requested"] = every_layout(
        Seed(request=UNKNOWN, levels=2).tree(0, [True])).build(chosen=1)
    s["invalid_max_levels_63_binary"] = Seed(levels_byte=0xF6).tree(0, [True]).build()
    s["invalid_duplicate_slot"] = Seed(slots=True, levels=2).tree(0, [True]).tree(1, []).build(
        slot_defect=5)
    s["invalid_misaligned_tuple_address"] = base().field(INT64, INDIRECT, defect=24).build()
    s["invalid_refined_beyond_max_levels"] = Seed(levels=2).tree(
        0, [True, True], defect=52).build()
    s["invalid_strided_stride_too_small"] = base().field(
        FLOAT32, STRIDED, components=2, defect=25).build()
    return s


def write(directory):
    os.makedirs(directory, exist_ok=True)
    for name, data in seeds().items():
        with open(os.path.join(directory, name), "wb") as out:
            out.write(data)


def check(fuzzer, directory):
    def judge(name, line):
        outcome = line.rsplit("; ", 1)[-1] if line else None
        wanted = {"valid": "built", "invalid": "refused"}.get(name.split("_")[0])
        if outcome and (wanted is None or outcome == wanted):
            return None
        return "%s, wanted %s" % (outcome, wanted)

    return corpus_check.check(fuzzer, directory, seeds(), "make_corpus.py",
                              "canopy fuzz input:", judge, "all seeds as named")


if __name__ == "__main__":
    corpus_check.main(__doc__, write, check)
