"""Our integrators and forces come back as their own classes from OpenMM's own calls.

OpenMM's Python layer turns a C++ `Integrator*` or `Force*` into the Python class of each of
OpenMM's own types, but knows nothing of a plugin's: `XmlSerializer.deserialize` of a
ShardlowIntegrator, or `System.getForce` of a DPDSoftRepulsionForce, gave a base `Integrator`
or `Force` proxy, on which e.g. `getOrder()` is an AttributeError. Importing openmmdpd wraps
the few OpenMM functions that hand such objects out (`XmlSerializer.deserialize` and `clone`
through `XmlSerializer._deserializeIntegrator`, `_deserializeForce`, `_cloneIntegrator` and
`_cloneForce`; `System.getForce`, hence `getForces`; `CompoundIntegrator.getIntegrator`) so that
an object whose C++ class is one of ours is returned as that class. Everything else passes
through unchanged: only a proxy of exactly the base class is looked at, and OpenMM's own
types never come back as one.
"""
import functools

import openmm as _openmm


def _as_own_class(obj, classes):
    """`obj` as the first of `classes` its C++ object is (ownership moves to the new proxy), or
    `obj` itself when it is not a proxy of exactly the base class or none of `classes` fits."""
    if type(obj) not in (_openmm.Integrator, _openmm.Force):
        return obj
    for cls in classes:
        result = cls._cast(obj)
        if result is not None:
            # The new proxy owns the C++ object if `obj` did, so `obj` can go (and code that
            # takes over the object through `thisown`, as __setstate__ does, takes it whole).
            result.thisown, obj.thisown = obj.thisown, False
            return result
    return obj


def _returning_own_class(function, classes, static):
    if getattr(function, "_openmmdpd_wrapped", False):
        wrapper = function  # already wrapped (the package imported again, e.g. reloaded)
    else:
        @functools.wraps(function)
        def wrapper(*args, **kwargs):
            return _as_own_class(function(*args, **kwargs), classes)

        wrapper._openmmdpd_wrapped = True
    return staticmethod(wrapper) if static else wrapper


def install(integrators, forces):
    """Wrap OpenMM's functions that hand out base proxies; `integrators` and `forces` are our
    classes (each with a `_cast` that gives None for any other C++ class)."""
    integrators, forces = tuple(integrators), tuple(forces)
    serializer = _openmm.XmlSerializer
    for name, classes in (("_deserializeIntegrator", integrators), ("_cloneIntegrator", integrators),
                          ("_deserializeForce", forces), ("_cloneForce", forces)):
        setattr(serializer, name, _returning_own_class(getattr(serializer, name), classes, static=True))
    _openmm.System.getForce = _returning_own_class(_openmm.System.getForce, forces, static=False)
    _openmm.CompoundIntegrator.getIntegrator = _returning_own_class(_openmm.CompoundIntegrator.getIntegrator,
                                                                    integrators, static=False)
