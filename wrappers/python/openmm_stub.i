// Debian ships no OpenMM SWIG interface files.  Declaring the base class here, under
// OpenMM's own module name, makes SWIG derive our proxies from openmm.openmm.Integrator
// (and Force) and share its runtime type table, so Context, Simulation and XmlSerializer accept them.
%module openmm
namespace OpenMM {
class Integrator {
public:
    virtual ~Integrator();
    virtual void step(int steps) = 0;
};
class Force {
public:
    virtual ~Force();
};
class Context;
class System;
}
