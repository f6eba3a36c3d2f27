#ifndef OPENMMDPD_TESTHELPERS_H_
#define OPENMMDPD_TESTHELPERS_H_

// Systems and checks shared by the integrator tests.

#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmm/Context.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>

using namespace OpenMM;

namespace {

const double KT_KELVIN = 120.27236;  // kT = 1 kJ/mol

// A DPD fluid at density 4 in a cubic box: soft repulsion a (0 = ideal gas, no force).
inline System* makeFluid(int n, double a, std::vector<Vec3>& positions, unsigned seed = 5) {
    System* system = new System();
    const double box = std::cbrt(n / 4.0);
    system->setDefaultPeriodicBoxVectors(Vec3(box, 0, 0), Vec3(0, box, 0), Vec3(0, 0, box));
    for (int i = 0; i < n; i++)
        system->addParticle(1.0);
    if (a > 0) {
        CustomNonbondedForce* soft = new CustomNonbondedForce("a*(1-r)^2/2");
        soft->addGlobalParameter("a", a);
        soft->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
        soft->setCutoffDistance(1.0);
        for (int i = 0; i < n; i++)
            soft->addParticle({});
        system->addForce(soft);
    }
    else {
        // No conservative force, but the System must still say it is periodic.
        CustomBondForce* none = new CustomBondForce("0");
        none->setUsesPeriodicBoundaryConditions(true);
        system->addForce(none);
    }
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0, box);
    positions.resize(n);
    for (Vec3& r : positions)
        r = Vec3(uniform(rng), uniform(rng), uniform(rng));
    return system;
}

inline std::unique_ptr<Context> makeContext(System& system, Integrator& integrator, const std::string& platform,
                                            const std::vector<Vec3>& positions, int threads = 0, bool deterministic = false) {
    std::map<std::string, std::string> properties;
    if (platform == "CPU" && threads > 0)
        properties["Threads"] = std::to_string(threads);
    if (platform == "CPU" && deterministic)
        properties["DeterministicForces"] = "true";
    std::unique_ptr<Context> context(new Context(system, integrator, Platform::getPlatformByName(platform), properties));
    context->setPositions(positions);
    context->setVelocitiesToTemperature(KT_KELVIN, 11);
    return context;
}

/** Whether OpenMM has the platform here (OpenCL, CUDA: where their plugins loaded). */
inline bool platformExists(const std::string& platform) {
    try {
        Platform::getPlatformByName(platform);
        return true;
    }
    catch (const OpenMMException&) {
        return false;
    }
}

inline std::vector<std::string> platforms() {
    std::vector<std::string> names = {"Reference"};
#if OPENMMDPD_HAVE_CPU
    names.push_back("CPU");
#endif
    return names;
}

// The total momentum of unit-mass particles.
inline Vec3 totalMomentum(Context& context) {
    const State state = context.getState(State::Velocities);
    Vec3 p;
    for (const Vec3& v : state.getVelocities())
        p += v;
    return p;
}

/** max |a_i| over the particles. */
inline double maxNorm(const std::vector<Vec3>& a) {
    double m = 0;
    for (const Vec3& x : a)
        m = std::max(m, std::sqrt(x.dot(x)));
    return m;
}

/** max |a_i - b_i| over the particles. */
inline double maxDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double m = 0;
    for (size_t i = 0; i < a.size(); i++)
        m = std::max(m, std::sqrt((a[i] - b[i]).dot(a[i] - b[i])));
    return m;
}

/** max |a_i - b_i| at the nearest image along each axis of a cubic box of edge `edge`: two platforms may wrap differently. */
inline double maxImageDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double edge) {
    double m = 0;
    for (size_t i = 0; i < a.size(); i++) {
        Vec3 d = a[i] - b[i];
        for (int k = 0; k < 3; k++)
            d[k] -= edge * std::round(d[k] / edge);
        m = std::max(m, std::sqrt(d.dot(d)));
    }
    return m;
}

/** The pressure tensor's averaged parts: kinetic, conservative, thermostat, total. */
inline std::vector<std::vector<double>> pressureParts(const DPDPlugin::DPDThermostatIntegrator& integrator) {
    std::vector<std::vector<double>> parts;
    for (int part : {DPDPlugin::DPDThermostatIntegrator::PressureKinetic, DPDPlugin::DPDThermostatIntegrator::PressureConservative,
                     DPDPlugin::DPDThermostatIntegrator::PressureThermostat, DPDPlugin::DPDThermostatIntegrator::PressureTotal})
        parts.push_back(integrator.getAveragePressureTensor(part));
    return parts;
}

/** Each component of each part within `tolerance` times the part's largest component. */
inline void expectPressurePartsNear(const std::vector<std::vector<double>>& expected, const std::vector<std::vector<double>>& actual,
                                    double tolerance, const std::string& label) {
    for (size_t p = 0; p < expected.size(); p++) {
        double scale = 0;
        for (double x : expected[p])
            scale = std::max(scale, std::fabs(x));
        for (size_t k = 0; k < expected[p].size(); k++)
            EXPECT_NEAR(actual[p][k], expected[p][k], tolerance * scale) << label << ", pressure tensor part " << p << ", component " << k;
    }
}

/** max |a - b| / max |a| over the particles (0 if a is all zero). */
inline double relativeDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double difference = 0, scale = 0;
    for (size_t i = 0; i < a.size(); i++) {
        const Vec3 d = a[i] - b[i];
        difference = std::max(difference, std::sqrt(d.dot(d)));
        scale = std::max(scale, std::sqrt(a[i].dot(a[i])));
    }
    return scale > 0 ? difference / scale : difference;
}

/**
 * 10 steps, a checkpoint, 10 more steps; the state disturbed (new velocities, 3 steps), the
 * checkpoint loaded and 10 steps again: the same positions and velocities, bit for bit.
 */
inline void expectCheckpointContinuesBitForBit(Context& context, Integrator& integrator, const std::string& label) {
    const long long start = context.getState(0).getStepCount();
    integrator.step(10);
    std::stringstream checkpoint;
    context.createCheckpoint(checkpoint);
    integrator.step(10);
    const State first = context.getState(State::Positions | State::Velocities);
    context.setVelocitiesToTemperature(KT_KELVIN, 99);
    integrator.step(3);
    context.loadCheckpoint(checkpoint);
    EXPECT_EQ(context.getState(0).getStepCount(), start + 10) << label;
    integrator.step(10);
    const State second = context.getState(State::Positions | State::Velocities);
    EXPECT_EQ(second.getStepCount(), start + 20) << label;
    for (size_t i = 0; i < first.getPositions().size(); i++) {
        ASSERT_EQ(first.getPositions()[i], second.getPositions()[i]) << label << " particle " << i;
        ASSERT_EQ(first.getVelocities()[i], second.getVelocities()[i]) << label << " particle " << i;
    }
}

inline void expectErrorNaming(const std::function<void()>& action, const std::string& name) {
    try {
        action();
        ADD_FAILURE() << "no exception for " << name;
    }
    catch (const OpenMMException& e) {
        EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
}

} // namespace

#endif
