"""Checks that canopy.f90 binds every function of canopy.h, with the same
parameters in the same order and matching iso_c_binding types, and that no
pointer Canopy may keep after the call is an array dummy (which a compiler may
satisfy with a temporary copy, freed when the call returns). The structs of
canopy.h (canopy_block_strides) must have a bind(c) derived type of the same
name with the same components, in the same order, of matching kinds and extents.

Usage: python3 binding_signatures.py canopy.h canopy.f90
Exit status 0 when every function matches; the mismatches are printed otherwise."""
import re
import sys

# canopy_open takes an MPI_Comm, which Fortran cannot pass: canopy_open_f binds it.
NOT_BINDABLE = {"canopy_open"}

# C scalar types and the Fortran declaration of a `value` dummy of that type.
SCALARS = {
    "int": "integer(c_int)",
    "int64_t": "integer(c_int64_t)",
    "size_t": "integer(c_size_t)",
    "double": "real(c_double)",
    "MPI_Fint": "integer(c_int)",
}


def c_functions(header):
    """{name: (return type, [(type, name), ...])} from the prototypes in canopy.h."""
    text = re.sub(r"/\*.*?\*/", " ", open(header).read(), flags=re.S)
    functions = {}
    for match in re.finditer(r"([A-Za-z_][\w\s\*]*?)\b(canopy_\w+)\s*\(([^;{]*?)\)\s*;", text):
        result, name, parameters = match.group(1), match.group(2), match.group(3)
        result = " ".join(result.replace("*", " * ").split())
        params = []
        if parameters.strip() != "void":
            for parameter in parameters.split(","):
                words = " ".join(parameter.replace("*", " * ").split())
                ptype, pname = words.rsplit(" ", 1)
                params.append((ptype, pname))
        functions[name] = (result, params)
    return functions


def c_structs(header):
    """{name: [(type, member, extent), ...]} of the structs canopy.h defines
    (typedef struct name { ... } name;), extent 0 for a scalar member."""
    text = re.sub(r"/\*.*?\*/", " ", open(header).read(), flags=re.S)
    structs = {}
    for match in re.finditer(r"typedef\s+struct\s+(\w+)\s*\{(.*?)\}\s*(\w+)\s*;", text, re.S):
        name, body = match.group(1), match.group(2)
        members = []
        for declaration in body.split(";"):
            words = declaration.split()
            if not words:
                continue
            member = re.match(r"(\w+)(?:\[(\d+)\])?$", words[-1])
            members.append((" ".join(words[:-1]), member.group(1), int(member.group(2) or 0)))
        structs[name] = members
    return structs


def fortran_types(module):
    """{name: [(declaration, component, extent), ...]} of the bind(c) derived types."""
    text = open(module).read()
    types = {}
    pattern = re.compile(r"^\s*type\s*,\s*bind\(c\)\s*::\s*(\w+)(.*?)^\s*end\s+type",
                         re.M | re.S | re.I)
    for match in pattern.finditer(text):
        components = []
        for line in match.group(2).splitlines():
            line = line.split("!")[0].strip().lower()
            if "::" not in line:
                continue
            declaration, declared = (part.strip() for part in line.split("::", 1))
            for component in re.findall(r"(\w+)\s*(?:\((\d+)\))?\s*(?:=\s*[^,]+)?,?",
                                        declared):
                components.append((declaration, component[0], int(component[1] or 0)))
        types[match.group(1).lower()] = components
    return types


def check_structs(header, module, problems):
    """Each C struct against its Fortran derived type, component by component."""
    fortran = fortran_types(module)
    for name, members in sorted(c_structs(header).items()):
        if name not in fortran:
            problems.append(f"struct {name}: no bind(c) derived type of that name in canopy.f90")
            continue
        want = [(SCALARS.get(ctype, "?" + ctype), member, extent)
                for ctype, member, extent in members]
        if fortran[name] != want:
            problems.append(f"struct {name}: canopy.f90 has {fortran[name]}, canopy.h {want}")
        else:
            print(f"ok: struct {name}: {len(want)} components")


def fortran_interfaces(module):
    """{name: (kind, result, [argument names], {argument: declaration})} from canopy.f90."""
    text = open(module).read()
    text = re.sub(r"&\s*\n\s*(&)?", " ", text)  # join continuation lines
    interfaces = {}
    pattern = re.compile(
        r"^\s*(?:(type\(c_ptr\)|integer\(c_int\))\s+)?(function|subroutine)\s+(canopy_\w+)"
        r"\s*\(([^)]*)\)\s*bind\(c\)(.*?)^\s*end\s+(?:function|subroutine)",
        re.M | re.S | re.I)
    for match in pattern.finditer(text):
        result, kind, name, arguments, body = match.groups()
        names = [a.strip().lower() for a in arguments.split(",") if a.strip()]
        declarations = {}
        for line in body.splitlines():
            line = line.split("!")[0].strip().lower()
            if "::" not in line or line.startswith("import"):
                continue
            attributes, declared = line.split("::", 1)
            for argument in declared.split(","):
                declarations[argument.strip()] = " ".join(attributes.replace(" ", "").split(","))
        interfaces[name] = (kind.lower(), (result or "").lower(), names, declarations)
    return interfaces


def expected_declaration(ptype, structs):
    """What the Fortran dummy for a C parameter of type `ptype` must be (attributes
    joined by spaces, in the order iso_c_binding code writes them), and a reason.
    `structs`: the names of canopy.h's structs (passed by reference, as the derived
    type of the same name)."""
    stars = ptype.count("*")
    base = ptype.replace("const", "").replace("*", "").split()[0]
    if base in structs and stars == 1:
        if ptype.startswith("const"):
            return {f"type({base}) intent(in)"}, "a struct, copied during the call"
        return ({f"type({base}) intent(inout)"},
                "a struct Canopy fills, unchanged when the call fails (intent(out) would "
                "reset a default-initialized type on entry)")
    if ptype == "size_t *":
        return {"integer(c_size_t)", "integer(c_size_t) intent(out)"}, "a result Canopy sets"
    if stars == 0:
        return {SCALARS[base] + " value"}, "a scalar passed by value"
    if base == "char" and stars == 1:
        return ({"character(kind=c_char) dimension(*) intent(in)",
                 "character(kind=c_char) dimension(*)"},
                "a NUL-terminated string, copied during the call")
    if ptype.startswith("const void * const *"):
        return ({"type(c_ptr) dimension(*) intent(in)", "type(c_ptr) dimension(*)"},
                "a list of addresses, copied during the call")
    if stars == 2:
        return ({"type(c_ptr) intent(out)", "type(c_ptr) intent(inout)", "type(c_ptr)"},
                "a handle Canopy sets (by reference)")
    if ptype == "int *":
        return {"integer(c_int)", "integer(c_int) intent(out)"}, "a result Canopy sets"
    if ptype == "double *":
        return {"real(c_double)", "real(c_double) intent(out)"}, "a result Canopy sets"
    # Handles and every array Canopy may keep: an address by value, never an
    # array dummy a compiler could satisfy with a temporary copy.
    return {"type(c_ptr) value"}, "an address (c_loc of a target), as Canopy may keep it"


def main(header, module):
    c = c_functions(header)
    fortran = fortran_interfaces(module)
    structs = set(c_structs(header))
    problems = []
    check_structs(header, module, problems)
    if not c:
        problems.append("no function found in " + header)
    for name, (result, params) in sorted(c.items()):
        bound = name + "_f" if name in NOT_BINDABLE else name
        before = len(problems)
        if bound not in fortran:
            problems.append(f"{name}: not bound in canopy.f90")
            continue
        kind, fresult, arguments, declarations = fortran[bound]
        if name in NOT_BINDABLE:
            params = [("MPI_Fint", params[0][1])] + params[1:]
        want = {"void": ("subroutine", ""), "int": ("function", "integer(c_int)"),
                "const char *": ("function", "type(c_ptr)")}.get(result)
        if want != (kind, fresult):
            problems.append(f"{bound}: returns {fresult or kind}, canopy.h says {result}")
        if arguments != [p[1] for p in params]:
            problems.append(f"{bound}: arguments {arguments}, canopy.h has {[p[1] for p in params]}")
            continue
        for ptype, pname in params:
            allowed, why = expected_declaration(ptype, structs)
            got = declarations.get(pname, "(undeclared)")
            if got not in allowed:
                problems.append(f"{bound}: {pname} is '{got}', should be '{sorted(allowed)[0]}' "
                                f"({ptype}: {why})")
        if len(problems) == before:
            print(f"ok: {name}" + (f" (as {bound})" if bound != name else "")
                  + f": {len(params)} arguments")
    for name in sorted(set(fortran) - set(c) - {n + "_f" for n in NOT_BINDABLE}):
        problems.append(f"{name}: bound in canopy.f90 but not in canopy.h")
    for problem in problems:
        print("FAILED: " + problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
