"""Every function, method or VTK class a document names must still be in the code: the
drift this catches is a page saying the code calls something it no longer calls (docs
that said trees were built with vtkHyperTree::BuildFromBreadthFirstOrderDescriptor
after the builder had moved to InitializeForReader).

What is a name here: in docs/*.md and README.md, inside `code spans`, a qualified name
(`vtkHyperTree::InitializeForReader`, `canopy::GridBuilder`, `ForestDescription::revision`),
a call (`buildHyperTreeGrid()`, `canopy_catalyst.settings()`, `GetTree(index, create=true)`)
and a VTK class (`vtkHyperTreeGridGeometry`); in fenced code blocks, the same when they are
Canopy's or VTK's (`canopy...`, `vtk...`), since examples also call the C library, MPI,
p4est and ParaView's Python. Every identifier of the name must appear in the code as a
word, comments and docstrings left out (a comment saying why a function is not called
does not count as calling it).

Which code: the product's (adaptor/, pipelines/, miniapp/, tools/, examples/, cmake/,
scripts/, the top CMakeLists.txt) for every page; tests/ too for the pages about tests and
benchmarks (docs/testing.md, docs/benchmarks.md), which name what the tests call and what
the benchmarks measure.

A name a page mentions because Canopy does not use it (a VTK filter it replaces, a call it
avoids) goes in ALLOWED below, with the reason.

Usage: doc_names_exist.py <source dir> [page ...]   (pages relative to it; default: all)
"""
import io
import os
import re
import sys
import tokenize

# Names the pages mention precisely because Canopy's code does not use them (tests/bench
# excluded, except for docs/benchmarks.md and docs/testing.md), each with the reason.
ALLOWED = {
    # VTK and ParaView classes Canopy replaces, avoids or cannot use.
    "vtkHyperTreeGridAxisCut": "ParaView 5.11's slice, which the slice filter replaces (design.md)",
    "vtkXMLHyperTreeGridWriter": "VTK 9.2's .htg writer corrupts vectors: Canopy writes .htg itself",
    "vtkXMLPHyperTreeGridReader": "VTK 9.2's .phtg reader crashes: why the series is .vtm of .htg",
    "vtkPVTrivialProducer": "ParaView's producer, whose time warning the driver avoids (design.md)",
    "vtkCompactHyperTree": "VTK's only tree class, named for what VTK lacks (block forests)",
    "vtkHyperTreeGridGeometryEntry": "where VTK's own filters abort on masked grids (benchmarks.md)",
    "vtkSMLiveInsituLinkProxy": "ParaView's Live link the GUI drives (insitu.md); Canopy talks to it "
                                "through ParaView's Catalyst, not by name",
    "vtkPlanes": "vtkPlanes::SetFrustumPlanes: VTK's frustum convention, which Frustum.h follows",
    "vtkFrustumSelector": "VTK's frustum corners' order, which Frustum.h follows (filters.md)",
    # VTK, ParaView and Python calls the pages name because Canopy does not call them.
    "IsGlobalIndexImplicit": "vtkHyperTree::IsGlobalIndexImplicit answers the opposite of its "
                             "name in VTK 9.2: the filters use GetGlobalIndexStart() instead",
    "GetFieldName": "vtkCPInputDataDescription::GetFieldName returns freed memory: not called",
    "get_args": "paraview.catalyst.get_args() is empty under the legacy Catalyst API: not called",
    "AppendInittab": "PyImport_AppendInittab, which the Python door cannot use (design.md)",
    "InsituConnect": "vtkLiveInsituLink::InsituConnect, ParaView's code where a stalled viewer "
                     "aborts the simulation (insitu.md's limits of Live)",
    "UpdateTimeStep": "how a user of plain VTK 9.5+ reads a step of grid.vtkhdf (insitu.md)",
    "ParentToElderChild": "VTK's child table inside vtkHyperTree, named for what it costs",
    # deal.II calls and CMake macros dealii.md names because Canopy does not use them.
    "deal_ii_setup_target": "deal.II's CMake macro, which Canopy does not call (dealii.md says why)",
    "deal_ii_initialize_cached_variables": "deal.II's CMake macro, which Canopy does not call: it "
                                           "would set all of Canopy's flags (dealii.md)",
    "output_results": "step-40's output function, which the example's Canopy lines replace",
    "build_patches": "DataOut::build_patches, what the Canopy lines replace (the benchmark "
                     "calls it)",
    "distort_random": "GridTools::distort_random, a mesh Canopy refuses (dealii.md)",
    # Names that are not functions of any code here.
    "MeshBlock": "Athena++'s block class, what the block forest benchmark imitates",
    "CanopyExtractSelection1": "the name ParaView gives a filter's first instance (insitu.md)",
    "Ids3D": "a parameterised test's name, made by its name generator (\"Ids\" + \"3D\")",
    "rebuildHyperTreeGrid": "the made-up name planted once to see this test fail (testing.md)",
}

PRODUCT = ["adaptor", "pipelines", "miniapp", "tools", "examples", "cmake", "scripts", "CMakeLists.txt"]
EVERYTHING = PRODUCT + ["tests"]
# Every page may name what the product and its tests call; the benchmarks (tests/bench)
# count only for the pages about benchmarks and tests, since a benchmark calls VTK's
# alternatives to Canopy on purpose, to measure them.
# (tests/docs holds this test, whose allowlist names what the code does not call.)
PAGE_SCOPE = {"docs/testing.md": (EVERYTHING, ("tests/docs",)),
              "docs/benchmarks.md": (EVERYTHING, ("tests/docs",))}
DEFAULT_SCOPE = (EVERYTHING, ("tests/bench", "tests/docs"))
SOURCE_EXTENSIONS = (".h", ".hpp", ".c", ".cxx", ".cpp", ".py", ".f90", ".cmake", ".sh", ".xml",
                     ".plugin", ".in", ".supp")
# Namespaces and modules that are neither Canopy's nor VTK's.
FOREIGN = {"std", "boost", "testing", "sc", "p4est", "p8est", "h5py", "np", "numpy", "MPI", "os",
           "math"}
# Calls of the C and Python libraries and of arithmetic (formulas in the prose).
ARITHMETIC = {"log2", "log", "ceil", "floor", "sqrt", "abs", "min", "max", "exp", "sin", "cos",
              "abort", "exit", "printf", "malloc", "free", "sizeof", "len", "range", "print"}
# What VTK's macros define (vtkGetMacro(Name, ...) defines GetName, and so on).
MACROS = [(re.compile(r"\bvtkGet\w*Macro\(\s*(\w+)"), ["Get{}"]),
          (re.compile(r"\bvtkSet\w*Macro\(\s*(\w+)"), ["Set{}"]),
          (re.compile(r"\bvtkBooleanMacro\(\s*(\w+)"), ["{}On", "{}Off"])]
MACRO_WORDS = {"vtkTypeMacro": ["NewInstance", "SafeDownCast", "IsA", "GetClassName"],
               "vtkAbstractTemplateTypeMacro": ["NewInstance", "SafeDownCast", "IsA"],
               "vtkAOSArrayNewInstanceMacro": ["NewInstance"],
               "vtkStandardNewMacro": ["New"]}

QUALIFIED = re.compile(r"(?<![\w:.])((?:[A-Za-z_]\w*::)+~?[A-Za-z_]\w*)")
CALL = re.compile(r"(?<![\w:.$])([A-Za-z_][\w.]*)\s*\(")
VTK_CLASS = re.compile(r"(?<![\w:.])(vtk[A-Z]\w*)")
# A code span holding one camel-case identifier: a class, method, member or property
# (`InitializeForReader`, `buildHyperTreeGrid`, `PreserveTopology`); not CONSTANTS.
BARE = re.compile(r"[A-Z][a-z0-9]+(?:[A-Z][a-z0-9]*)+|[a-z][a-z0-9]*(?:[A-Z][a-z0-9]*)+")
SPAN = re.compile(r"(`+)(.+?)\1", re.S)
FENCE = re.compile(r"^```[^\n]*\n(.*?)^```[ \t]*$", re.S | re.M)


def strip_c(text):
    """C/C++ without comments (strings and character literals kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = n if j < 0 else j + 2
            out.append(" ")
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            open_paren = text.find("(", i)
            delimiter = text[i + 2:open_paren]
            j = text.find(")" + delimiter + '"', open_paren)
            j = n if j < 0 else j + len(delimiter) + 2
            out.append(text[i:j])
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def strip_python(text):
    """Python without comments and docstrings."""
    kept = []
    previous = tokenize.NEWLINE
    try:
        for token in tokenize.generate_tokens(io.StringIO(text).readline):
            if token.type == tokenize.COMMENT:
                continue
            if token.type == tokenize.STRING and previous in (tokenize.NEWLINE, tokenize.INDENT,
                                                              tokenize.DEDENT, tokenize.NL):
                continue  # a string statement: a docstring
            if token.type not in (tokenize.NL,):
                previous = token.type
            kept.append(token.string)
    except (tokenize.TokenError, IndentationError, SyntaxError):
        return re.sub(r"#[^\n]*", "", text)
    return " ".join(kept)


def strip_hash(text):
    """Shell, CMake: '#' to the end of the line (a '#' inside quotes is kept)."""
    out = []
    for line in text.splitlines():
        quote = None
        for k, c in enumerate(line):
            if quote:
                if c == quote:
                    quote = None
            elif c in "\"'":
                quote = c
            elif c == "#" and (k == 0 or line[k - 1] in " \t;(") and not line[k:].startswith("#!"):
                line = line[:k]
                break
        out.append(line)
    return "\n".join(out)


def strip_fortran(text):
    return "\n".join(re.sub(r"!.*", "", line) if "'" not in line and '"' not in line else line
                     for line in text.splitlines())


def code_words(root, tops, excluded):
    """Every identifier in the code under `tops` (not under `excluded`), comments left out,
    with the methods VTK's macros define."""
    words = set()
    for top in tops:
        path = os.path.join(root, top)
        files = [path] if os.path.isfile(path) else [
            os.path.join(d, f) for d, subdirs, names in os.walk(path)
            for f in names if not d.split(os.sep)[-1].startswith(".")]
        for name in files:
            relative = os.path.relpath(name, root)
            if relative.startswith("build") or "/fixtures/" in name or any(
                    relative.startswith(e + os.sep) for e in excluded):
                continue
            base = os.path.basename(name)
            if not (base.endswith(SOURCE_EXTENSIONS) or base == "CMakeLists.txt"):
                continue
            if base.endswith(".txt") and base != "CMakeLists.txt":
                continue
            try:
                with open(name, encoding="utf-8", errors="replace") as f:
                    text = f.read()
            except OSError:
                continue
            if base.endswith((".h", ".hpp", ".c", ".cxx", ".cpp")):
                text = strip_c(text)
            elif base.endswith(".py"):
                text = strip_python(text)
            elif base.endswith((".cmake", ".sh")) or base == "CMakeLists.txt" or base.endswith(".in"):
                text = strip_hash(text)
            elif base.endswith(".f90"):
                text = strip_fortran(text)
            elif base.endswith((".xml", ".plugin")):
                text = re.sub(r"<!--.*?-->", "", text, flags=re.S)
            words.update(re.findall(r"[A-Za-z_]\w*", text))
            for pattern, forms in MACROS:
                for match in pattern.finditer(text):
                    words.update(form.format(match.group(1)) for form in forms)
            for macro, defined in MACRO_WORDS.items():
                if macro in text:
                    words.update(defined)
    return words


def names_in(page_text):
    """(line, name, identifiers to find) for every checked name of a page."""
    found = []

    def add(line, name, parts):
        parts = [p for p in parts if p and not p.startswith("~")]
        if parts:
            found.append((line, name, parts))

    def scan(text, offset, canopy_or_vtk_only):
        line_of = lambda position: page_text.count("\n", 0, offset + position) + 1
        taken = []
        for match in QUALIFIED.finditer(text):
            name = match.group(1)
            parts = name.split("::")
            if parts[0] in FOREIGN:
                continue
            if canopy_or_vtk_only and not (parts[0] == "canopy" or parts[0].startswith("vtk")):
                continue
            taken.append(match.span())
            add(line_of(match.start()), name, [p for p in parts if p != "canopy"])
        for match in CALL.finditer(text):
            if any(a <= match.start() < b for a, b in taken):
                continue
            name = match.group(1)
            last = name.split(".")[-1]
            if canopy_or_vtk_only and not re.match(r"(canopy|Canopy|_canopy|vtk)", name):
                continue
            if name.split(".")[0] in FOREIGN or name in ARITHMETIC:
                continue
            add(line_of(match.start()), name + "()", [last])
        if not canopy_or_vtk_only:
            bare = BARE.fullmatch(text.strip())
            if bare and not text.strip().startswith("vtk"):
                add(line_of(0), text.strip(), [text.strip()])
        for match in VTK_CLASS.finditer(text):
            if any(a <= match.start() < b for a, b in taken):
                continue
            name = match.group(1)
            add(line_of(match.start()), name, [name])

    fences = list(FENCE.finditer(page_text))
    for fence in fences:
        scan(fence.group(1), fence.start(1), True)
    position = 0
    for start, end in [f.span() for f in fences] + [(len(page_text), len(page_text))]:
        prose = page_text[position:start]
        for span in SPAN.finditer(prose):
            scan(span.group(2), position + span.start(2), False)
        position = end
    return found


def main():
    root = os.path.abspath(sys.argv[1])
    pages = sys.argv[2:] or (["README.md"] + sorted(
        os.path.join("docs", f) for f in os.listdir(os.path.join(root, "docs")) if f.endswith(".md")))
    scopes = {}
    problems, checked = [], 0
    for page in pages:
        tops, excluded = PAGE_SCOPE.get(page, DEFAULT_SCOPE)
        key = (tuple(tops), tuple(excluded))
        if key not in scopes:
            scopes[key] = code_words(root, tops, excluded)
        words = scopes[key]
        with open(os.path.join(root, page), encoding="utf-8") as f:
            text = f.read()
        for line, name, parts in names_in(text):
            checked += 1
            missing = [p for p in parts if p not in words and p not in ALLOWED
                       and not (p.endswith("s") and p[:-1] in words)  # a plural: vtkHyperTrees
                       and not {"Set" + p, "Get" + p, p + "On"} & words]  # a VTK property
            if missing:
                problems.append("%s:%d: `%s`: %s not in the code%s" % (
                    page, line, name, ", ".join(missing),
                    " (tests/bench excluded)" if "tests/bench" in excluded else ""))
    if problems:
        print("Names the documents give that the code does not have (comments excluded).")
        print("Fix the page, or, if it names them because Canopy does not use them, add them to")
        print("ALLOWED in tests/docs/doc_names_exist.py with the reason:")
        for problem in problems:
            print("  " + problem)
        return 1
    print("%d names in %d pages are all in the code" % (checked, len(pages)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
