"""Public headers are included one way, and no include runs up the layers.

(a) Every #include of a public header (adaptor/include/canopy/..., in the sources,
    tests, benchmarks and the docs' code) names it by its path under adaptor/include
    in angle brackets: <canopy/X.h>, <canopy/io/X.h>, <canopy/filters/X.h>, never
    by its bare name ("X.h", <X.h>) nor in quotes.
(b) A public header includes only public headers (<canopy/...>), VTK's (<vtk*.h>),
    MPI's (<mpi.h>), the standard library's, and the export header VTK generates
    for its module ("CanopyFiltersModule.h", "CanopyIOModule.h"): never a private
    header, which is not installed. The deal.II bridge's header (canopy/DealIIForest.h)
    takes deal.II's types in its API and so includes deal.II's headers (<deal.II/...>)
    too: its users are deal.II programs.
(c) No include runs up the layers (docs/design.md): adaptor/common includes only
    adaptor/common; adaptor/forest common and the core public headers; adaptor/filters
    and adaptor/io (each its own) common, forest and the core public headers;
    adaptor/insitu, adaptor/p4est and adaptor/dealii any of those. A public header of a folder under
    adaptor/include is held to the folder's library.

Usage: include_layers.py <source dir>
"""
import os
import re
import sys

root = sys.argv[1]
public_root = os.path.join(root, "adaptor", "include")
INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*([<"])([^>"]+)[>"]', re.M)
SCANNED = (".h", ".hpp", ".c", ".cc", ".cpp", ".cxx", ".md", ".txt", ".in")

# The public headers: bare name -> path under adaptor/include ("canopy/io/X.h").
public = {}
for directory, _, files in os.walk(public_root):
    for name in files:
        if name.endswith(".h"):
            path = os.path.relpath(os.path.join(directory, name), public_root)
            public[name] = path.replace(os.sep, "/")

# Layers, bottom up; a folder may include its own headers and those of lower layers.
# The public headers count as their library's: canopy/ as the forest's, canopy/io as
# Canopy::IO's, canopy/filters as Canopy::Filters'.
LAYER = {"common": 0, "forest": 1, "include/canopy": 1, "filters": 2, "io": 2,
         "include/canopy/filters": 2, "include/canopy/io": 2, "insitu": 3, "p4est": 3,
         "dealii": 3}
SAME = {"include/canopy": "forest", "include/canopy/filters": "filters", "include/canopy/io": "io"}


def home(folder):
    """The library a folder of adaptor/ belongs to, for the same-layer rule."""
    return SAME.get(folder, folder)


# Private headers of adaptor/: bare name -> folders that have one by that name.
private = {}
for folder in LAYER:
    if folder.startswith("include"):
        continue
    directory = os.path.join(root, "adaptor", folder)
    for name in os.listdir(directory) if os.path.isdir(directory) else []:
        if name.endswith(".h"):
            private.setdefault(name, set()).add(folder)

STANDARD = set("""algorithm any array atomic bitset cassert cctype cerrno cfloat charconv
chrono cinttypes climits clocale cmath complex condition_variable csignal cstdarg cstddef
cstdint cstdio cstdlib cstring ctime cwchar deque exception execution filesystem forward_list
fstream functional future initializer_list iomanip ios iosfwd iostream istream iterator limits
list locale map memory memory_resource mutex new numeric optional ostream queue random ratio
regex scoped_allocator set shared_mutex sstream stack stdexcept streambuf string string_view
system_error thread tuple type_traits typeindex typeinfo unordered_map unordered_set utility
valarray variant vector""".split()) | {"stddef.h", "stdint.h", "stdbool.h", "stdio.h",
                                         "stdlib.h", "string.h", "mpi.h"}
GENERATED = re.compile(r"Canopy\w*Module\.h")


# Public headers of bridges whose API is another library's types, and what they may include.
BRIDGE_INCLUDES = {"DealIIForest.h": re.compile(r"deal\.II/[\w/.]+\.h")}


def public_include_problem(bracket, name, header=""):
    """Why a public header may not include `name` (None: it may)."""
    bridge = BRIDGE_INCLUDES.get(header)
    if bracket == "<" and bridge is not None and bridge.fullmatch(name):
        return None
    if name.startswith("canopy/"):
        if bracket != "<" or name[len("canopy/"):] not in \
                {p[len("canopy/"):] for p in public.values()}:
            return "not a public header as <canopy/...>"
        return None
    if bracket == '"' and GENERATED.fullmatch(name):
        return None
    if bracket == "<" and (name in STANDARD or re.fullmatch(r"vtk\w+\.h", name)):
        return None
    return "neither public, VTK's, MPI's, standard nor the generated export header"


problems = []
for top, directories, files in os.walk(root):
    relative_top = os.path.relpath(top, root)
    if relative_top == ".":
        # Build trees (build*/) hold generated code (ParaView's wrappers include
        # the classes' headers by their bare names); .git holds history.
        directories[:] = [d for d in directories if not d.startswith(("build", "."))]
    for file_name in files:
        if not file_name.endswith(SCANNED):
            continue
        path = os.path.join(top, file_name)
        relative = os.path.relpath(path, root).replace(os.sep, "/")
        try:
            text = open(path, encoding="utf-8").read()
        except UnicodeDecodeError:
            continue
        parts = relative.split("/")
        folder = None  # the adaptor folder (or public folder) this file is in
        if parts[0] == "adaptor" and len(parts) > 2:
            folder = "/".join(parts[1:-1])
        for match in INCLUDE.finditer(text):
            bracket, name = match.group(1), match.group(2)
            line = text.count("\n", 0, match.start()) + 1
            where = "%s:%d: #include %s%s%s" % (relative, line, bracket, name,
                                                ">" if bracket == "<" else '"')
            base = name.split("/")[-1]
            # (a) a public header: by its path, in angle brackets.
            if base in public and name != public[base] and base not in private:
                problems.append("%s: a public header, include it as <%s>" % (where, public[base]))
                continue
            if name in public.values() and bracket != "<":
                problems.append("%s: include public headers in angle brackets" % where)
                continue
            if folder is None or folder not in LAYER:
                continue
            # (b) public headers include nothing private.
            if folder.startswith("include"):
                why = public_include_problem(bracket, name, file_name)
                if why:
                    problems.append("%s: a public header includes %s" % (where, why))
                    continue
            # (c) nothing runs up the layers.
            if name.startswith("canopy/"):
                target = "/".join(["include"] + name.split("/")[:-1])
                targets = {target} if target in LAYER else set()
            elif base == name and base in private:
                targets = private[base]
                if folder in targets:
                    continue  # its own folder's header
            else:
                continue
            for target in targets:
                if home(target) == home(folder):
                    continue
                if LAYER[target] >= LAYER[folder]:
                    problems.append("%s: adaptor/%s includes a header of adaptor/%s, not a "
                                    "lower layer" % (where, folder, target))

if problems:
    print("\n".join(problems))
    sys.exit("%d include(s) break the rules above (%s)" % (len(problems), __file__))
print("%d public headers; every include follows the rules" % len(public))
