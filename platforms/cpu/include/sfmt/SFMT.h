// Debian's libopenmm-dev lacks this header, which openmm/cpu/CpuRandom.h includes; that
// header only needs the class name.
namespace OpenMM_SFMT { class SFMT; }
