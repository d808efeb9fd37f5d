"""docs/design.md's "Components" section must name every component file of the
product and nothing that is not there: each source, header and script under
adaptor/, pipelines/, miniapp/, tools/ and examples/ by its stem (CellSlots
for CellSlots.h and CellSlots.cxx), listed under its folder. A file added,
renamed or removed without the design document following fails this test.

Usage: design_names_every_file.py <source dir>
"""
import os
import re
import sys

root = sys.argv[1]
design = open(os.path.join(root, "docs", "design.md")).read()
match = re.search(r"^## Components\n(.*?)^## ", design, re.S | re.M)
if match is None:
    sys.exit("docs/design.md has no '## Components' section")
block = re.search(r"```\n(.*?)```", match.group(1), re.S)
if block is None:
    sys.exit("docs/design.md's Components section has no file listing (``` block)")
listing = block.group(1)

# The listing: a folder line ("adaptor/forest/   what it is") and below it,
# indented, one or more stems per line ("  CellSlots   what it is", or
# "  vtkCanopyXMLP{PolyData,UnstructuredGrid}Writer" for a family).
named = {}
folder = None
for line in listing.splitlines():
    if not line.strip():
        continue
    if not line.startswith(" "):
        folder = line.split()[0].rstrip("/")
        named.setdefault(folder, set())
        continue
    if folder is None or len(line) - len(line.lstrip()) != 2:
        continue  # a continuation of the description above
    first = line.split()[0]
    family = re.fullmatch(r"([\w.]*)\{([\w,.]+)\}([\w.]*)", first)
    stems = [family.group(1) + part + family.group(3) for part in family.group(2).split(",")] \
        if family else [first]
    for stem in stems:
        named[folder].add(stem.split(".")[0] if not stem.endswith((".xml", ".plugin")) else stem)

extensions = (".h", ".cxx", ".py", ".f90", ".xml", ".plugin")
problems = []
present = {}
for top in ("adaptor", "pipelines", "miniapp", "tools", "examples"):
    for directory, _, files in os.walk(os.path.join(root, top)):
        relative = os.path.relpath(directory, root)
        for name in files:
            if not name.endswith(extensions):
                continue
            stem = name if name.endswith((".xml", ".plugin")) else name.split(".")[0]
            present.setdefault(relative, set()).add(stem)

for folder, stems in sorted(present.items()):
    if folder not in named:
        problems.append("folder %s/ is not in the listing" % folder)
        continue
    for stem in sorted(stems - named[folder]):
        problems.append("%s/%s is not named" % (folder, stem))
for folder, stems in sorted(named.items()):
    for stem in sorted(stems - present.get(folder, set())):
        problems.append("%s/%s is named but does not exist" % (folder, stem))

if problems:
    print("docs/design.md's Components listing does not match the tree:")
    for problem in problems:
        print("  " + problem)
    sys.exit(1)
print("docs/design.md names all %d component files' stems in %d folders"
      % (sum(len(s) for s in present.values()), len(present)))
