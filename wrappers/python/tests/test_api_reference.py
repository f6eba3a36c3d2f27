"""The API reference (docs/api/) documents the whole public API: every class of the public
C++ headers openmmapi/include/openmmdpd/*.h with each of its public methods, every free
function there, and every name of `openmmdpd.__all__` (the classes with their methods, the
modules (openmmdpd.scenes, ...) with their `__all__`).

Reads the site that scripts/docs.sh built into docs/_build/html, and is skipped when there
is none, or when it is older than the headers, the docs/api pages or the package it is built
from (the test suite runs before the site is built; docs.sh runs this file after it builds
the site, so the check always runs there).  An entry is the anchor Sphinx gives a documented
object, not a mention in prose: a C++ object's id in Sphinx's C++ domain (_CPPv4N9DPDPlugin...),
a Python object's dotted name.

Left out: openmmdpd/internal/ (not installed API) and openmmdpd/DPDKernels.h, the kernel
interfaces between the API and the platforms (docs/api/index.md says so).  Destructors, and
the protected and private members, are not required."""
import functools
import glob
import inspect
import os
import re

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
HEADERS = os.path.join(ROOT, "openmmapi", "include", "openmmdpd")
SITE_API = os.path.join(ROOT, "docs", "_build", "html", "api")
NOT_DOCUMENTED = {"DPDKernels.h"}


def public_headers():
    return sorted(path for path in glob.glob(os.path.join(HEADERS, "*.h"))
                  if os.path.basename(path) not in NOT_DOCUMENTED)


# --- A small parse of the headers ----------------------------------------------------------

def strip_comments_and_preprocessor(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    text = re.sub(r"^\s*#[^\n]*", " ", text, flags=re.M)
    return re.sub(r'"(?:\\.|[^"\\])*"', '""', text)


def matching_brace(text, start):
    """The index just after the brace that closes the one at text[start]."""
    depth = 0
    for i in range(start, len(text)):
        if text[i] == "{":
            depth += 1
        elif text[i] == "}":
            depth -= 1
            if depth == 0:
                return i + 1
    raise ValueError("unbalanced braces")


def top_level_declarations(body):
    """The declarations of a scope's body, in order, with the bodies of functions cut out:
    an access specifier ('public:') comes as a declaration of its own, and a nested class,
    struct or enum as (its head, its body)."""
    declarations, current, i = [], "", 0
    while i < len(body):
        c = body[i]
        if c == "{":
            end = matching_brace(body, i)
            if "(" in current:  # a function's body: the declaration ends with it
                declarations.append(current)
            else:  # a nested class, struct or enum: its head and its body
                declarations.append((current.strip(), body[i + 1:end - 1]))
            current = ""
            i = end
            continue
        if c == ";":
            declarations.append(current)
            current = ""
        else:
            current += c
            access = re.search(r"\b(public|protected|private)\s*:(?!:)$", current)
            if access:
                declarations.append(access.group(1) + ":")
                current = ""
        i += 1
    declarations.append(current)
    return [d if isinstance(d, tuple) else d.strip() for d in declarations
            if isinstance(d, tuple) or d.strip()]


CLASS_HEAD = re.compile(r"^(?:template\s*<[^>]*>\s*)?(class|struct)\s+([A-Za-z_]\w*)\b")
NAMESPACE_HEAD = re.compile(r"^namespace\s+(\w+)$")


def function_name(declaration):
    """The name a function declaration declares, or None (data members, types, friends,
    templates, destructors, operators)."""
    if "(" not in declaration or re.match(r"(friend|typedef|using|enum|struct|class|template)\b", declaration):
        return None
    match = re.search(r"(~?)\s*([A-Za-z_]\w*)\s*$", declaration[:declaration.index("(")])
    if not match or match.group(1) or match.group(2).startswith("operator"):
        return None
    return match.group(2)


def parse_scope(body, scope, access, classes):
    """The public methods (the functions, for the namespace: scope ()) declared in a
    namespace's or a class's body; adds its public classes to `classes`, as
    {(outer, ..., name): sorted public method names}."""
    methods = set()
    for declaration in top_level_declarations(body):
        if isinstance(declaration, tuple):
            klass = CLASS_HEAD.match(declaration[0])
            if klass and access == "public":
                inner = scope + (klass.group(2),)
                classes[inner] = sorted(parse_scope(declaration[1], inner,
                                                    "public" if klass.group(1) == "struct" else "private", classes))
        elif declaration in ("public:", "protected:", "private:"):
            access = declaration[:-1]
        elif access == "public" and function_name(declaration):
            methods.add(function_name(declaration))
    return methods


def parse_header(path):
    """({(class, ...): sorted public method names}, [free function names]) of namespace
    DPDPlugin in a header."""
    with open(path, encoding="utf-8") as source:
        text = strip_comments_and_preprocessor(source.read())
    classes, functions = {}, []
    for declaration in top_level_declarations(text):
        if isinstance(declaration, tuple) and NAMESPACE_HEAD.match(declaration[0]) \
                and NAMESPACE_HEAD.match(declaration[0]).group(1) == "DPDPlugin":
            functions += sorted(parse_scope(declaration[1], (), "public", classes))
    return classes, functions


def test_the_header_parse_finds_what_a_header_declares():
    """The parse itself, on a header written for it."""
    text = """
        namespace OpenMM { class System; }
        namespace DPDPlugin {
        /** A class { with braces in a comment } and a "string;" */
        class A : public OpenMM::Integrator {
        public:
            A(double x, const std::string& name = "a;b") : x(x) {}
            virtual ~A();
            double getX() const { return x; }
            enum Part { PartOne = 0, PartTwo = 1 };
            std::vector<double> getAverage(int part = PartOne) const;
            struct Pair { int i, j; };
        protected:
            void initialize(OpenMM::ContextImpl& context) override;
        private:
            void check() const;
            double x;
        };
        void loadIt(OpenMM::Context& context, std::istream& stream);
        }
    """
    import tempfile
    with tempfile.NamedTemporaryFile("w", suffix=".h", delete=False) as header:
        header.write(text)
    try:
        assert parse_header(header.name) == ({("A",): ["A", "getAverage", "getX"], ("A", "Pair"): []}, ["loadIt"])
    finally:
        os.unlink(header.name)


@functools.lru_cache(maxsize=None)
def public_api():
    """([(class, [public methods])], [free functions]) of every public header."""
    classes, functions = [], []
    for path in public_headers():
        header_classes, header_functions = parse_header(path)
        classes += sorted(header_classes.items())
        functions += header_functions
    return classes, functions


def test_the_public_headers_declare_what_the_reference_must_hold():
    """The parse finds the API it is meant to check (a parse that found nothing would pass
    everything below)."""
    classes, functions = public_api()
    names = {"::".join(scope): methods for scope, methods in classes}
    for name in ("DPDThermostatIntegrator", "DPDVVIntegrator", "ShardlowIntegrator", "LoweAndersenIntegrator",
                 "EDPDIntegrator", "StaggeredDPDIntegrator", "DenOtterClarkeIntegrator", "DPDSoftRepulsionForce",
                 "ParticleTypeTable", "ParticleTypeTable::TypePair"):
        assert name in names, name
    assert {"getTemperature", "setShearRate", "getAveragePressureTensor", "step"} <= set(names["DPDThermostatIntegrator"])
    assert "initialize" not in names["DPDThermostatIntegrator"]  # protected
    assert "checkTemperature" not in names["DPDThermostatIntegrator"]  # private
    assert "loadCheckpoint" in functions


# --- The site --------------------------------------------------------------------------------

@functools.lru_cache(maxsize=None)
def site_anchors():
    """Every id="..." of the API reference's pages."""
    pages = glob.glob(os.path.join(SITE_API, "**", "*.html"), recursive=True)
    anchors = set()
    for page in pages:
        with open(page, encoding="utf-8") as html:
            anchors.update(re.findall(r'\bid="([^"]+)"', html.read()))
    return anchors


def needs_site():
    """Skips without a site, and with one older than what it is built from (a site left from
    an earlier build would report what has changed since as missing)."""
    where = os.path.relpath(SITE_API, ROOT)
    if not os.path.isdir(SITE_API):
        pytest.skip(f"no documentation site in {where} (bash scripts/docs.sh builds it and then runs this test)")
    import openmmdpd
    sources = public_headers() + glob.glob(os.path.join(ROOT, "docs", "api", "*.md")) \
        + glob.glob(os.path.join(os.path.dirname(openmmdpd.__file__), "*.py"))
    newest = max(sources, key=os.path.getmtime)
    pages = glob.glob(os.path.join(SITE_API, "*.html"))
    if not pages or os.path.getmtime(newest) > min(map(os.path.getmtime, pages)):
        pytest.skip(f"the documentation site in {where} is older than {os.path.relpath(newest, ROOT)} "
                    f"(bash scripts/docs.sh builds it again and then runs this test)")


def cpp_ids(*names):
    """The starts of the ids Sphinx's C++ domain (id version 4) gives DPDPlugin::names[0]::
    names[1]...: N9DPDPlugin..., NK9DPDPlugin... for a const member function.  A function's
    id goes on with its parameter types, so every overload starts so."""
    nested = "9DPDPlugin" + "".join(f"{len(name)}{name}" for name in names)
    return ("_CPPv4N" + nested, "_CPPv4NK" + nested)


def documented(*names):
    return any(anchor.startswith(cpp_ids(*names)) for anchor in site_anchors())


def test_every_public_cpp_class_and_method_is_in_the_reference():
    needs_site()
    classes, functions = public_api()
    missing = []
    for scope, methods in classes:
        name = "::".join(scope)
        # a class's own id ends in E; its members' ids go on with theirs
        if cpp_ids(*scope)[0] + "E" not in site_anchors():
            missing.append(f"class DPDPlugin::{name}")
            continue
        missing += [f"DPDPlugin::{name}::{method}()" for method in methods
                    if not documented(*scope, method)]
    missing += [f"DPDPlugin::{function}()" for function in functions if not documented(function)]
    assert not missing, (f"the C++ API reference (docs/api/*.md, built into {os.path.relpath(SITE_API, ROOT)}) "
                         f"lacks: {', '.join(missing)}")


def test_every_name_of_openmmdpd_all_is_in_the_reference():
    needs_site()
    import openmmdpd
    anchors = site_anchors()
    missing = []
    for name in openmmdpd.__all__:
        obj = getattr(openmmdpd, name)
        if inspect.ismodule(obj):
            if f"module-openmmdpd.{name}" not in anchors:
                missing.append(f"the module openmmdpd.{name}")
            missing += [f"openmmdpd.{name}.{member}" for member in obj.__all__
                        if f"openmmdpd.{name}.{member}" not in anchors]
            continue
        if f"openmmdpd.{name}" not in anchors:
            missing.append(f"openmmdpd.{name}")
            continue
        if isinstance(obj, type):
            # the methods the class itself defines (inherited ones are under their class)
            missing += [f"openmmdpd.{name}.{member}" for member, value in vars(obj).items()
                        if not member.startswith("_") and member != "thisown" and callable(value)
                        and f"openmmdpd.{name}.{member}" not in anchors]
    assert not missing, (f"the Python API reference (docs/api/python*.md, built into "
                         f"{os.path.relpath(SITE_API, ROOT)}) lacks: {', '.join(missing)}")
