#ifndef OPENMMDPD_TESTSCHEMES_H_
#define OPENMMDPD_TESTSCHEMES_H_

// Every single-rate integrator and variant, by name, for the tests that run them all.

#include "TestHelpers.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace {

struct Scheme {
    std::string name;
    std::function<DPDPlugin::DPDThermostatIntegrator*()> make;
    bool uniformMasses = false;  // the integrator takes one mass only
};

inline void PrintTo(const Scheme& scheme, std::ostream* out) {
    *out << scheme.name;
}

/** GW (lambda 1/2 and 0.65), DPD-VV, SC-VV, S1, S2, Lowe, pair OU (both splittings), EDPD (both), OC; gamma 4.5, rc 1, kT 1. */
inline std::vector<Scheme> schemesAt(double dt) {
    using namespace DPDPlugin;
    auto dpdvv = [dt](DPDVVIntegrator::Variant variant, double lambda) {
        DPDVVIntegrator* integrator = new DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, dt);
        integrator->setVariant(variant);
        integrator->setLambda(lambda);
        return (DPDThermostatIntegrator*) integrator;
    };
    auto shardlow = [dt](int order) {
        ShardlowIntegrator* integrator = new ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, dt);
        integrator->setOrder(order);
        return (DPDThermostatIntegrator*) integrator;
    };
    auto lowe = [dt](LoweAndersenIntegrator::Method method, LoweAndersenIntegrator::Splitting splitting) {
        LoweAndersenIntegrator* integrator = new LoweAndersenIntegrator(KT_KELVIN, 4.5, 1.0, dt);
        integrator->setMethod(method);
        integrator->setSplitting(splitting);
        return (DPDThermostatIntegrator*) integrator;
    };
    auto edpd = [dt](EDPDIntegrator::Scheme scheme) {
        EDPDIntegrator* integrator = new EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 10.0, dt);
        integrator->setScheme(scheme);
        return (DPDThermostatIntegrator*) integrator;
    };
    auto denOtterClarke = [dt] {
        // Model B's averages (Nikunen et al. 2003, Table III)
        DenOtterClarkeIntegrator* integrator = new DenOtterClarkeIntegrator(KT_KELVIN, 4.5, 1.0, dt);
        integrator->setAverageFDDotV(-4.985245);
        integrator->setAverageFDDotFD(14.507340);
        integrator->setAverageFRDotFR(9.976453);
        return (DPDThermostatIntegrator*) integrator;
    };
    const LoweAndersenIntegrator::Splitting after = LoweAndersenIntegrator::AfterVerlet, middle = LoweAndersenIntegrator::Middle;
    return {
        {"GW-0.5", [=] { return dpdvv(DPDVVIntegrator::GrootWarren, 0.5); }},
        {"GW-0.65", [=] { return dpdvv(DPDVVIntegrator::GrootWarren, 0.65); }},
        {"DPD-VV", [=] { return dpdvv(DPDVVIntegrator::DPDVV, 0.5); }},
        {"SC-VV", [=] { return dpdvv(DPDVVIntegrator::SelfConsistent, 0.5); }},
        {"S1", [=] { return shardlow(1); }},
        {"S2", [=] { return shardlow(2); }},
        {"Lowe", [=] { return lowe(LoweAndersenIntegrator::Lowe, after); }},
        {"PairOU", [=] { return lowe(LoweAndersenIntegrator::PairOrnsteinUhlenbeck, after); }},
        {"Lowe-mid", [=] { return lowe(LoweAndersenIntegrator::Lowe, middle); }},
        {"PairOU-mid", [=] { return lowe(LoweAndersenIntegrator::PairOrnsteinUhlenbeck, middle); }},
        {"EDPD-OneSided", [=] { return edpd(EDPDIntegrator::OneSided); }},
        {"EDPD-Symmetric", [=] { return edpd(EDPDIntegrator::Symmetric); }},
        {"OC", denOtterClarke, true},
    };
}

/**
 * StaggeredDPDIntegrator with both bases at K = 1 and 3, the parameters Symeonidis and
 * Karniadakis 2006 recommend (weighted); gamma (vV) or Gamma (Lowe) 4.5, rc 1, kT 1.  The System needs a force in
 * group 1, the default fast group.
 */
inline std::vector<Scheme> staggeredSchemesAt(double dt) {
    using namespace DPDPlugin;
    auto staggered = [dt](StaggeredDPDIntegrator::BaseScheme base, int k) {
        StaggeredDPDIntegrator* integrator = new StaggeredDPDIntegrator(KT_KELVIN, 4.5, 1.0, dt, k);
        integrator->setBaseScheme(base);
        integrator->useRecommendedParameters();
        return (DPDThermostatIntegrator*) integrator;
    };
    const StaggeredDPDIntegrator::BaseScheme vv = StaggeredDPDIntegrator::VelocityVerlet, lowe = StaggeredDPDIntegrator::LoweAndersen;
    return {
        {"Staggered-vV-K1", [=] { return staggered(vv, 1); }},
        {"Staggered-vV-K3", [=] { return staggered(vv, 3); }},
        {"Staggered-Lowe-K1", [=] { return staggered(lowe, 1); }},
        {"Staggered-Lowe-K3", [=] { return staggered(lowe, 3); }},
    };
}

} // namespace

#endif
