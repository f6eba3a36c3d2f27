"""DPD force fields in OpenMM's own ForceField XML format (docs/guide/force-fields.md).

Importing this module registers these tags with OpenMM's `app.forcefield.parsers`, so that
`app.ForceField` reads them beside its own (`AtomTypes`, `Residues`, `HarmonicBondForce`,
`HarmonicAngleForce`, ...):

- `DPDSoftRepulsionForce`: `<Pair type1 type2 a cutoff/>` (kJ/mol/nm, nm), one
  `DPDSoftRepulsionForce` with a particle type per bead type;
- `DPDThermostat`: `<Pair type1 type2 friction cutoff [weightExponent] [transverseFriction]
  [transverseWeightExponent]/>` (1/ps, nm; the exponent s of the weights, 2 by default; the
  transverse friction, 0 by default, and its exponent, 2), the integrator's type-pair table, and on the tag
  itself the optional `bondFactor12` and `bondFactor13` (1 by default), the thermostat factors
  of bonded pairs and of pairs two bonds apart; `apply_thermostat_parameters` copies them into
  an integrator;
- `FENEBondForce`: `<Bond class1 class2 k rmax/>`;
- `WormLikeChainBondForce`: `<Bond class1 class2 persistenceLength springLength kT/>`;
- `CosineAngleForce`: `<Angle class1 class2 class3 k theta0/>`, k (1 - cos(theta - theta0)).

A pair or bond may name types (`type1`) or classes (`class1`), as OpenMM's tags do. Bead
types are atom types without an element; a residue made only of beads is matched to the
template with the same bead names and bonds (see `match_bead_residue`).
"""
import math
import os
import weakref

import openmm
from openmm import app, unit
from openmm.app import forcefield as _openmm_forcefield
from openmm.app.internal import compiled

from .dpdplugin import DPDSoftRepulsionForce, DPDThermostatIntegrator
from .packer import Molecule

__all__ = ["data_path", "apply_thermostat_parameters", "bead_types", "match_bead_residue", "LIPID_H3T4",
           "SoftRepulsionGenerator", "ThermostatGenerator", "FENEBondGenerator", "WormLikeChainBondGenerator",
           "CosineAngleGenerator"]

# The folder of the force fields shipped with the package.
DATA_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")

#: The residue LIPID of lipid-h3t4.xml for the packer: beads h1-h3, then two tails t1-t4 and
#: t5-t8 both bonded to h3.
LIPID_H3T4 = Molecule.single("LIPID", ["h1", "h2", "h3"] + [f"t{i}" for i in range(1, 9)],
                             [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 6), (2, 7), (7, 8), (8, 9), (9, 10)])


def data_path(name):
    """The path of a force field shipped with the package, e.g. data_path("groot-warren.xml")."""
    path = os.path.join(DATA_DIR, name)
    if not os.path.isfile(path):
        shipped = sorted(f for f in os.listdir(DATA_DIR) if f.endswith(".xml")) if os.path.isdir(DATA_DIR) else []
        raise ValueError(f"no force field {name!r} is shipped with openmmdpd; shipped: {', '.join(shipped) or 'none'}")
    return path


# --- Bead residues ---------------------------------------------------------------------------

def _is_bead_template(template):
    return all(atom.element is None for atom in template.atoms)


# {ForceField: (template ids, templates, {sorted bead names: [templates]})}, so that matching a
# residue looks at the few templates with its bead names rather than at all of them. The key is
# the templates' identities, not their number: a template registered with a higher override
# level replaces one of the same name, leaving the number unchanged. The cache holds the
# templates themselves so that none of their ids can be reused while it stands.
_BEAD_TEMPLATES = weakref.WeakKeyDictionary()


def _bead_templates_by_names(forcefield):
    """{sorted bead names: [templates]} for the element-less templates, rebuilt when templates change."""
    templates = tuple(forcefield._templates.values())
    key = tuple(map(id, templates))
    cached = _BEAD_TEMPLATES.get(forcefield)
    if cached is None or cached[0] != key:
        index = {}
        for template in templates:
            if _is_bead_template(template):
                index.setdefault(tuple(sorted(atom.name for atom in template.atoms)), []).append(template)
        cached = _BEAD_TEMPLATES[forcefield] = (key, templates, index)
    return cached[2]


def _describe_residue(residue):
    return f"residue {residue.index} ({residue.name}) with beads {', '.join(atom.name for atom in residue.atoms())}"


def match_bead_residue(forcefield, residue, bondedToAtom, ignoreExternalBonds, ignoreExtraParticles):
    """OpenMM's template matcher for residues made only of element-less atoms (beads).

    OpenMM's own matching keys templates by element counts, which are empty for every bead
    template, and lets an element-less atom match any template atom whose name the template
    lacks: a one-bead residue would match every one-bead template. Here a bead residue
    matches only templates with exactly its bead names, then OpenMM's matcher checks the
    bonds (internal and external).

    A residue none of them matches is left to OpenMM (None) when OpenMM's own matching finds
    no template either: createSystem then tries patches and template generators and reports
    "No template found", and getUnmatchedResidues lists the residue. Where OpenMM's matching
    would take a template with other bead names, that would give the beads wrong types
    silently, so it is an error naming the residue, its beads and that template; so are two
    matching templates with different bead types. Residues with elements are left to OpenMM.
    """
    if any(atom.element is not None for atom in residue.atoms()):
        return None
    names = tuple(sorted(atom.name for atom in residue.atoms()))
    matches = []
    for template in _bead_templates_by_names(forcefield).get(names, ()):
        match = compiled.matchResidueToTemplate(residue, template, bondedToAtom, ignoreExternalBonds,
                                                ignoreExtraParticles)
        if match is not None:
            matches.append((template, match))
    if not matches:
        # The templates OpenMM's own matching would try next: those with no element, by the
        # signature it gives them (no elements, the empty signature).
        loose = next((template for template in forcefield._templateSignatures.get("", ())
                      if compiled.matchResidueToTemplate(residue, template, bondedToAtom, ignoreExternalBonds,
                                                         ignoreExtraParticles) is not None), None)
        if loose is None:
            return None
        raise ValueError(f"no bead template matches {_describe_residue(residue)}: a template needs the same "
                         f"bead names and the same bonds, external bonds included (OpenMM's matching by "
                         f"elements would take {loose.name}, with beads "
                         f"{', '.join(atom.name for atom in loose.atoms)})")
    first, first_match = matches[0]
    for template, match in matches[1:]:
        if not first.areParametersIdentical(template, first_match, match):
            raise ValueError(f"bead templates {first.name} and {template.name} both match "
                             f"{_describe_residue(residue)} with different types; pass residueTemplates "
                             f"to choose one")
    return first


def _register(forcefield, generator_class):
    """The force field's generator of this class, created (with the bead matcher) on first use."""
    for generator in forcefield.getGenerators():
        if isinstance(generator, generator_class):
            return generator
    generator = generator_class(forcefield)
    forcefield.registerGenerator(generator)
    if match_bead_residue not in forcefield._templateMatchers:
        forcefield.registerTemplateMatcher(match_bead_residue)
    return generator


def _is_periodic(data, nonbondedMethod, tag):
    """Periodic when the topology has a box, unless CutoffNonPeriodic is asked for."""
    if nonbondedMethod not in (app.NoCutoff, app.CutoffPeriodic, app.CutoffNonPeriodic):
        raise ValueError(f"{tag}: nonbondedMethod {nonbondedMethod} does not apply to DPD forces; "
                         f"use CutoffPeriodic (or NoCutoff: periodic in the topology's box) or CutoffNonPeriodic")
    if nonbondedMethod == app.CutoffNonPeriodic or not data.atoms:
        return False
    return data.atoms[0].residue.chain.topology.getPeriodicBoxVectors() is not None


# --- Type-pair tables --------------------------------------------------------------------------

def bead_types(forcefield, type_names):
    """The distinct type names among `type_names`, in the force field's order of <AtomTypes>.

    A type's index in this list is the particle type the force and the integrator give it.
    """
    present = set(type_names)
    return [name for name in forcefield._atomTypes if name in present]


# A value's allowed range, as an entry's error message states it.
_CONDITIONS = {">= 0": lambda value: value >= 0, "> 0": lambda value: value > 0, None: lambda value: True}


def _parse_entry(forcefield, tag, kind, attrib, num_types, values, defaults):
    """(type sets, values) of one <Pair>, <Bond> or <Angle>, checked in full before anything keeps
    it. values: {attribute: its range (">= 0", "> 0" or None)}; defaults: {attribute: its value
    where the entry omits it}, for the optional ones. An unknown type or class, or a missing
    required value, a non-numeric or non-finite value, or one out of its range, is an error
    naming the entry."""
    types = forcefield._findAtomTypes(attrib, num_types)
    if None in types:
        raise ValueError(f"{tag}: {kind} {dict(attrib)} names a type or class the force field lacks")
    missing = [name for name in values if name not in attrib and name not in defaults]
    if missing:
        raise ValueError(f"{tag}: {kind} {dict(attrib)} lacks {', '.join(missing)}")
    try:
        numbers = tuple(float(attrib[name]) if name in attrib else defaults[name] for name in values)
    except ValueError:
        numbers = (math.nan,)
    if not all(math.isfinite(number) for number in numbers):
        raise ValueError(f"{tag}: {kind} {dict(attrib)}: {', '.join(values)} must be finite numbers")
    if not all(_CONDITIONS[condition](number) for number, condition in zip(numbers, values.values())):
        needs = " and ".join(f"{name} {condition}" for name, condition in values.items() if condition)
        raise ValueError(f"{tag}: {kind} {dict(attrib)} needs {needs}")
    return [set(t) for t in types], numbers


def _parse_entries(forcefield, generator_class, element):
    """Every entry of a tag, parsed before the generator is created or given any, so that a bad
    entry leaves the force field as it was."""
    return [_parse_entry(forcefield, generator_class.tag, generator_class.kind, child.attrib,
                         generator_class.num_types, generator_class.values, generator_class.defaults)
            for child in element.findall(generator_class.kind)]


class _PairTable:
    """Per-type-pair values of one tag's <Pair> or <Bond> entries, given by type or class; the
    first matching entry wins, whichever order the pair's types come in."""

    def __init__(self, tag):
        self.tag = tag
        self.entries = []

    def lookup(self, type1, type2):
        for (types1, types2), values in self.entries:
            if (type1 in types1 and type2 in types2) or (type1 in types2 and type2 in types1):
                return values
        return None

    def table(self, types):
        """{(i, j): values} for i <= j indices into `types`; a pair without an entry is an error."""
        result = {}
        for i, type1 in enumerate(types):
            for j in range(i, len(types)):
                values = self.lookup(type1, types[j])
                if values is None:
                    raise ValueError(f"{self.tag}: no entry for the type pair ({type1}, {types[j]})")
                result[(i, j)] = values
        return result


class _PairTableGenerator:
    """A generator whose tag holds <Pair> or <Bond> entries of a type pair (a _PairTable)."""
    tag = kind = None
    num_types = 2
    values = {}  # attribute: its range
    defaults = {}  # optional attribute: its value where an entry omits it

    def __init__(self, forcefield):
        self.forcefield = forcefield
        self.table = _PairTable(self.tag)

    @classmethod
    def parseElement(cls, element, forcefield):
        entries = _parse_entries(forcefield, cls, element)
        _register(forcefield, cls).table.entries.extend(entries)


def _check_same_pairs(forcefield, types):
    """Refuse a force field whose a_ij and friction tables cover different pairs of `types`."""
    force = _generator(forcefield, SoftRepulsionGenerator)
    thermostat = _generator(forcefield, ThermostatGenerator)
    if force is None or thermostat is None:
        return
    for i, type1 in enumerate(types):
        for type2 in types[i:]:
            has_a = force.table.lookup(type1, type2) is not None
            has_friction = thermostat.table.lookup(type1, type2) is not None
            if has_a != has_friction:
                lacking = "DPDThermostat (friction)" if has_a else "DPDSoftRepulsionForce (a_ij)"
                raise ValueError(f"the type pair ({type1}, {type2}) is in one type-pair table but not in "
                                 f"{lacking}: the force and the thermostat must cover the same pairs")


def _generator(forcefield, generator_class):
    return next((g for g in forcefield.getGenerators() if isinstance(g, generator_class)), None)


class SoftRepulsionGenerator(_PairTableGenerator):
    """`<DPDSoftRepulsionForce>`: a `DPDSoftRepulsionForce` with a_ij and cutoff per type pair.

    Every bead is a particle type (bead_types' order); every pair of types in the topology
    needs an entry. The XML's cutoffs are the model's: createSystem's nonbondedCutoff is not
    used. Bonded beads repel too, as in Groot and Warren's chains (no exclusions).
    """
    tag, kind = "DPDSoftRepulsionForce", "Pair"
    values = {"a": ">= 0", "cutoff": "> 0"}

    def createForce(self, system, data, nonbondedMethod, nonbondedCutoff, args):
        names = [data.atomType[atom] for atom in data.atoms]
        types = bead_types(self.forcefield, names)
        if not types:
            return
        table = self.table.table(types)
        force = DPDSoftRepulsionForce(*table[(0, 0)])
        force.setNonbondedMethod(DPDSoftRepulsionForce.CutoffPeriodic if _is_periodic(data, nonbondedMethod, self.tag)
                                 else DPDSoftRepulsionForce.CutoffNonPeriodic)
        _set_particle_types(force, names, types)
        for (i, j), (a, cutoff) in table.items():
            if (i, j) != (0, 0):  # the defaults hold pair (0, 0)
                force.addTypePair(i, j, a, cutoff)
        system.addForce(force)


def _set_particle_types(target, names, types):
    index = {name: i for i, name in enumerate(types)}
    for particle, name in enumerate(names):
        target.setParticleType(particle, index[name])


class ThermostatGenerator(_PairTableGenerator):
    """`<DPDThermostat>`: the integrators' friction (1/ps), cutoff (nm), weight exponent
    (2 by default) and transverse friction (1/ps, 0 by default) with its exponent (2) per type
    pair, and the tag's bondFactor12 and bondFactor13 (1 by default): the thermostat factors of
    the pairs one and two bonds apart.

    It adds no force (the thermostat is the integrator's); createSystem only checks that
    it covers the same type pairs as `<DPDSoftRepulsionForce>`.
    """
    tag, kind = "DPDThermostat", "Pair"
    values = {"friction": ">= 0", "cutoff": "> 0", "weightExponent": "> 0", "transverseFriction": ">= 0",
              "transverseWeightExponent": "> 0"}
    defaults = {"weightExponent": 2.0, "transverseFriction": 0.0, "transverseWeightExponent": 2.0}

    def __init__(self, forcefield):
        super().__init__(forcefield)
        self.bondFactors = {}  # the factors the tags gave: {attribute: factor}

    @classmethod
    def parseElement(cls, element, forcefield):
        factors = _parse_bond_factors(element.attrib, _generator(forcefield, cls))
        entries = _parse_entries(forcefield, cls, element)
        generator = _register(forcefield, cls)
        generator.bondFactors.update(factors)
        generator.table.entries.extend(entries)

    def bond_factors(self):
        """(factor12, factor13), 1 where no tag gives one."""
        return tuple(self.bondFactors.get(name, 1.0) for name in _BOND_FACTORS)

    def createForce(self, system, data, nonbondedMethod, nonbondedCutoff, args):
        _check_same_pairs(self.forcefield, bead_types(self.forcefield, data.atomType.values()))


# <DPDThermostat>'s own attributes: {attribute: the pairs whose thermostat it scales}.
_BOND_FACTORS = {"bondFactor12": "one bond apart", "bondFactor13": "two bonds apart"}


def _parse_bond_factors(attrib, generator):
    """{attribute: factor} of the bond factors a <DPDThermostat> gives, each in [0, 1] and the
    same as an earlier tag's, so that a file loaded later cannot change them silently."""
    factors = {}
    for name, pairs in _BOND_FACTORS.items():
        if name not in attrib:
            continue
        try:
            factor = float(attrib[name])
        except ValueError:
            factor = math.nan
        if not 0 <= factor <= 1:  # NaN fails too
            raise ValueError(f"DPDThermostat: {name}={attrib[name]!r} must be a number in [0, 1], the factor "
                             f"of the thermostat of beads {pairs} (1: as other pairs, 0: excluded)")
        earlier = generator.bondFactors.get(name, factor) if generator is not None else factor
        if earlier != factor:
            raise ValueError(f"DPDThermostat: {name}={attrib[name]!r} differs from the {earlier!r} of an earlier "
                             f"<DPDThermostat>")
        factors[name] = factor
    return factors


class _CustomBondGenerator(_PairTableGenerator):
    """A periodic CustomBondForce whose per-bond parameters come from type-pair <Bond> entries."""
    kind = "Bond"
    expression = name = None
    parameters = ()  # the per-bond parameter of each of `values`, in order

    def createForce(self, system, data, nonbondedMethod, nonbondedCutoff, args):
        force = openmm.CustomBondForce(self.expression)
        force.setName(self.name)
        for parameter in self.parameters:
            force.addPerBondParameter(parameter)
        for bond in data.bonds:
            values = self.table.lookup(data.atomType[data.atoms[bond.atom1]], data.atomType[data.atoms[bond.atom2]])
            if values is not None:
                force.addBond(bond.atom1, bond.atom2, values)
        if force.getNumBonds():
            force.setUsesPeriodicBoundaryConditions(_is_periodic(data, nonbondedMethod, self.tag))
            system.addForce(force)


class FENEBondGenerator(_CustomBondGenerator):
    """`<FENEBondForce>`: -k/2 rmax^2 ln(1 - r^2/rmax^2), as scenes.fene_bond_force (NaN past rmax)."""
    tag, name = "FENEBondForce", "FENE"
    expression = "-k*rmax^2*log(sqrt(1 - (r/rmax)^2))"
    values = {"k": ">= 0", "rmax": "> 0"}
    parameters = ("k", "rmax")


class WormLikeChainBondGenerator(_CustomBondGenerator):
    """`<WormLikeChainBondForce>`: Marko–Siggia springs as scenes.wlc_bond_force, with
    persistenceLength lp (nm), springLength L (nm) and kT (kJ/mol) per type pair."""
    tag, name = "WormLikeChainBondForce", "WormLikeChain"
    expression = "kT/lp*L*(0.25*exp(-log(1 - R)) - 0.25 - 0.25*R + 0.5*R^2); R=r/L"
    values = {"persistenceLength": "> 0", "springLength": "> 0", "kT": ">= 0"}
    parameters = ("lp", "L", "kT")


class CosineAngleGenerator:
    """`<CosineAngleForce>`: k (1 - cos(theta - theta0)) per angle of bonded beads (k in kJ/mol,
    theta0 in radians; theta0 = pi keeps a chain straight)."""
    tag, kind, num_types = "CosineAngleForce", "Angle", 3
    values = {"k": ">= 0", "theta0": None}
    defaults = {}

    def __init__(self, forcefield):
        self.entries = []

    @classmethod
    def parseElement(cls, element, forcefield):
        entries = _parse_entries(forcefield, cls, element)
        _register(forcefield, cls).entries.extend(entries)

    def parameters(self, type1, type2, type3):
        for (types1, types2, types3), values in self.entries:
            if type2 in types2 and ((type1 in types1 and type3 in types3) or (type1 in types3 and type3 in types1)):
                return values
        return None

    def createForce(self, system, data, nonbondedMethod, nonbondedCutoff, args):
        force = openmm.CustomAngleForce("k*(1 - cos(theta - theta0))")
        force.setName("CosineAngle")
        force.addPerAngleParameter("k")
        force.addPerAngleParameter("theta0")
        for angle in data.angles:
            values = self.parameters(*(data.atomType[data.atoms[i]] for i in angle))
            if values is not None:
                force.addAngle(*angle, values)
        if force.getNumAngles():
            force.setUsesPeriodicBoundaryConditions(_is_periodic(data, nonbondedMethod, self.tag))
            system.addForce(force)


# --- The thermostat's table into an integrator ---------------------------------------------------

def _thermostat_integrator_classes():
    # OpenMM 8.3 and later has a DPDIntegrator with the same type-pair model.
    return (DPDThermostatIntegrator,) + ((openmm.DPDIntegrator,) if hasattr(openmm, "DPDIntegrator") else ())


def _atom_type_names(forcefield, topology, residueTemplates, ignoreExternalBonds):
    """Each atom's type name, by the same template matching createSystem does."""
    data = app.ForceField._SystemData(topology)
    forcefield._matchAllResiduesToTemplates(data, topology, residueTemplates, ignoreExternalBonds)
    return [data.atomType[atom] for atom in topology.atoms()]


def apply_thermostat_parameters(integrator, forcefield, topology, residueTemplates=None, ignoreExternalBonds=False,
                                system=None):
    """Copy the force field's `<DPDThermostat>` table for the types in `topology` into `integrator`.

    Sets every particle's type with the numbering the force's particle types have (bead_types),
    the defaults to the friction, cutoff and weight exponent of type pair (0, 0) and a type pair
    for every other pair, so no pair falls back on a default set elsewhere. Where the tag's
    bondFactor12 or bondFactor13 is not 1, adds the thermostat exceptions of the topology's
    bonds (createThermostatExceptionsFromBonds). Refuses an integrator that already has type
    pairs, a force field whose friction and a_ij tables cover different pairs, and weight
    exponents other than 2 or bond factors for an integrator without them (OpenMM's
    DPDIntegrator). residueTemplates and ignoreExternalBonds: as given to createSystem.

    The types come from matching the topology's residues again. system: the System createSystem
    made; given, each particle's type is checked against its DPDSoftRepulsionForce, and a
    particle whose two types differ (other residueTemplates or ignoreExternalBonds, or a force
    field changed since) is an error naming it, before the integrator is changed. Returns the
    integrator.
    """
    if not isinstance(integrator, _thermostat_integrator_classes()):
        raise TypeError(f"apply_thermostat_parameters: {type(integrator).__name__} has no type-pair "
                        f"thermostat; give one of openmmdpd's integrators")
    thermostat = _generator(forcefield, ThermostatGenerator)
    if thermostat is None:
        raise ValueError("apply_thermostat_parameters: the force field has no <DPDThermostat>")
    if integrator.getNumTypePairs():
        raise ValueError(f"apply_thermostat_parameters: the integrator already has {integrator.getNumTypePairs()} "
                         f"type pairs; give it a new integrator")
    names = _atom_type_names(forcefield, topology, residueTemplates or {}, ignoreExternalBonds)
    types = bead_types(forcefield, names)
    if system is not None:
        _check_system_types(forcefield, system, names, types)
    if not types:
        return integrator
    _check_same_pairs(forcefield, types)
    table = thermostat.table.table(types)
    factors = thermostat.bond_factors()
    _check_thermostat_options(integrator, table, factors)
    if factors != (1.0, 1.0):
        # First: it is the one change that can still be refused, and it then changes nothing.
        _create_bond_exceptions(integrator, topology, factors)
    _set_type_pairs(integrator, table)
    _set_particle_types(integrator, names, types)
    return integrator


def _check_thermostat_options(integrator, table, factors):
    """Refuse weight exponents other than 2, transverse friction or bond factors for an integrator that lacks them."""
    if isinstance(integrator, DPDThermostatIntegrator):
        return
    lacking = [what for what, used in (("weight exponents", any(values[2] != 2.0 for values in table.values())),
                                       ("transverse friction", any(values[3] != 0 for values in table.values())),
                                       ("thermostat exceptions", factors != (1.0, 1.0))) if used]
    if lacking:
        raise ValueError(f"apply_thermostat_parameters: {type(integrator).__name__} has no "
                         f"{' and no '.join(lacking)}, which the force field's <DPDThermostat> sets "
                         f"(weightExponent other than 2, transverseFriction, bondFactor12 or bondFactor13 other "
                         f"than 1); give one of openmmdpd's integrators")


def _create_bond_exceptions(integrator, topology, factors):
    bonds = [(atom1.index, atom2.index) for atom1, atom2 in topology.bonds()]
    try:
        integrator.createThermostatExceptionsFromBonds(bonds, *factors)
    except openmm.OpenMMException as error:
        raise ValueError(f"apply_thermostat_parameters: the bond factors' exceptions: {error}") from error


def _set_type_pairs(integrator, table):
    """The defaults from type pair (0, 0) and a type pair for every other one; the weight
    exponents and transverse friction only where the integrator has them (OpenMM's
    DPDIntegrator has not)."""
    options = isinstance(integrator, DPDThermostatIntegrator)
    friction, cutoff, exponent, perpendicular, perpendicular_exponent = table[(0, 0)]
    integrator.setDefaultFriction(friction)
    integrator.setDefaultCutoff(cutoff)
    if options:
        integrator.setDefaultWeightExponent(exponent)
        integrator.setDefaultTransverseFriction(perpendicular)
        integrator.setDefaultTransverseWeightExponent(perpendicular_exponent)
    for (i, j), (friction, cutoff, exponent, perpendicular, perpendicular_exponent) in table.items():
        if (i, j) != (0, 0):
            index = integrator.addTypePair(i, j, friction, cutoff)
            if options:
                integrator.setTypePairWeightExponent(index, exponent)
                integrator.setTypePairTransverseFriction(index, perpendicular, perpendicular_exponent)


def _check_system_types(forcefield, system, names, types):
    """Refuse a System whose DPDSoftRepulsionForce gives the particles other types than matching
    the topology did (names: each particle's type name; types: their numbering)."""
    where = "apply_thermostat_parameters"
    advice = "give the ForceField, residueTemplates and ignoreExternalBonds that createSystem was given"
    if system.getNumParticles() != len(names):
        raise ValueError(f"{where}: system has {system.getNumParticles()} particles, the topology "
                         f"{len(names)} atoms; give the System createSystem made from this topology")
    force = next((f for f in system.getForces() if isinstance(f, DPDSoftRepulsionForce)), None)
    if force is None:
        if types:
            raise ValueError(f"{where}: system has no DPDSoftRepulsionForce to take the particle types from")
        return
    index = {name: i for i, name in enumerate(types)}
    for particle, name in enumerate(names):
        if force.getParticleType(particle) != index[name]:
            raise ValueError(f"{where}: particle {particle} is type {index[name]} ({name}) by matching the "
                             f"topology but type {force.getParticleType(particle)} in the System's "
                             f"DPDSoftRepulsionForce; {advice}")
    # The same numbers can stand for other types (a template overridden since createSystem):
    # the force's a_ij and cutoffs must then be the force field's for the types matched.
    generator = _generator(forcefield, SoftRepulsionGenerator)
    if generator is None or not types:
        return
    applied = {(i, j): (_number(force.getDefaultA()), _number(force.getDefaultCutoff()))
               for i in range(len(types)) for j in range(i, len(types))}
    for k in range(force.getNumTypePairs()):
        i, j, a, cutoff = force.getTypePairParameters(k)
        applied[(min(i, j), max(i, j))] = (_number(a), _number(cutoff))
    for (i, j), values in generator.table.table(types).items():
        if not all(math.isclose(x, y, rel_tol=1e-12) for x, y in zip(values, applied.get((i, j), (math.nan,) * 2))):
            raise ValueError(f"{where}: the System's DPDSoftRepulsionForce has a, cutoff = {applied.get((i, j))} "
                             f"for type pair ({i}, {j}), the force field {values} for ({types[i]}, {types[j]}) "
                             f"as the topology matches; {advice}")


def _number(value):
    return value.value_in_unit(value.unit) if unit.is_quantity(value) else float(value)


for _generator_class in (SoftRepulsionGenerator, ThermostatGenerator, FENEBondGenerator,
                         WormLikeChainBondGenerator, CosineAngleGenerator):
    _openmm_forcefield.parsers[_generator_class.tag] = _generator_class.parseElement
