#include "openmmdpd/DPDSerializationHelpers.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/serialization/SerializationNode.h"
#include <cerrno>
#include <climits>
#include <cstdlib>

using namespace DPDPlugin;
using OpenMM::SerializationNode;

void XmlReader::refuse(const char* name, const std::string& why) const {
    const std::string where = node.getName().empty() ? "" : " of <" + printable(node.getName()) + ">";
    throw OpenMM::OpenMMException(owner + ": cannot read the XML: attribute " + name + where + " " + why);
}

const std::string& XmlReader::text(const char* name) const {
    if (!node.hasProperty(name))
        refuse(name, "is missing");
    return node.getStringProperty(name);
}

double XmlReader::number(const char* name) const {
    const std::string& value = text(name);
    char* end = nullptr;
    const double x = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0')
        refuse(name, "is \"" + printable(value) + "\", not a number");
    return x;
}

double XmlReader::number(const char* name, double defaultValue) const {
    return node.hasProperty(name) ? number(name) : defaultValue;
}

int XmlReader::integer(const char* name) const {
    const std::string& value = text(name);
    char* end = nullptr;
    errno = 0;
    const long long n = std::strtoll(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || errno == ERANGE || n < INT_MIN || n > INT_MAX)
        refuse(name, "is \"" + printable(value) + "\", not an integer from " + std::to_string(INT_MIN) + " to " +
                     std::to_string(INT_MAX));
    return (int) n;
}

int XmlReader::integer(const char* name, int defaultValue) const {
    return node.hasProperty(name) ? integer(name) : defaultValue;
}

bool XmlReader::flag(const char* name) const {
    // OpenMM writes bools as "true"/"false" or "1"/"0" depending on its version.
    const std::string& value = text(name);
    if (value == "1" || value == "true")
        return true;
    if (value == "0" || value == "false")
        return false;
    refuse(name, "is \"" + printable(value) + "\", not true or false");
}

bool XmlReader::flag(const char* name, bool defaultValue) const {
    return node.hasProperty(name) ? flag(name) : defaultValue;
}

XmlReader XmlReader::child(const char* name) const {
    for (const SerializationNode& c : node.getChildren())
        if (c.getName() == name)
            return XmlReader(c, owner);
    throw OpenMM::OpenMMException(owner + ": cannot read the XML: <" + printable(node.getName()) + "> has no <" + name +
                                  "> element");
}

bool XmlReader::hasChild(const char* name) const {
    for (const SerializationNode& c : node.getChildren())
        if (c.getName() == name)
            return true;
    return false;
}

std::vector<XmlReader> XmlReader::children() const {
    std::vector<XmlReader> result;
    for (const SerializationNode& c : node.getChildren())
        result.emplace_back(c, owner);
    return result;
}

void DPDPlugin::serializeThermostatParameters(const DPDThermostatIntegrator& integrator, SerializationNode& node) {
    node.setDoubleProperty("stepSize", integrator.getStepSize());
    node.setDoubleProperty("temperature", integrator.getTemperature());
    node.setDoubleProperty("defaultFriction", integrator.getDefaultFriction());
    node.setDoubleProperty("defaultCutoff", integrator.getDefaultCutoff());
    node.setDoubleProperty("constraintTolerance", integrator.getConstraintTolerance());
    node.setIntProperty("randomSeed", integrator.getRandomNumberSeed());
    node.setIntProperty("integrationForceGroups", integrator.getIntegrationForceGroups());
    node.setDoubleProperty("instabilityThreshold", integrator.getInstabilityThreshold());
    node.setDoubleProperty("shearRate", integrator.getShearRate());
    node.setBoolProperty("pressureTensorEnabled", integrator.getPressureTensorEnabled());
    node.setDoubleProperty("defaultWeightExponent", integrator.getDefaultWeightExponent());
    serializeTypeTable(integrator, node, "friction");
    SerializationNode& exponents = node.createChildNode("WeightExponents");
    for (int k = 0; k < integrator.getNumTypePairs(); k++)
        exponents.createChildNode("TypePair").setIntProperty("index", k).setDoubleProperty("s", integrator.getTypePairWeightExponent(k));
    node.setDoubleProperty("defaultTransverseFriction", integrator.getDefaultTransverseFriction());
    node.setDoubleProperty("defaultTransverseWeightExponent", integrator.getDefaultTransverseWeightExponent());
    SerializationNode& transverse = node.createChildNode("TransverseFriction");
    for (int k = 0; k < integrator.getNumTypePairs(); k++) {
        double friction, s;
        integrator.getTypePairTransverseFriction(k, friction, s);
        transverse.createChildNode("TypePair").setIntProperty("index", k).setDoubleProperty("friction", friction).setDoubleProperty("s", s);
    }
    SerializationNode& exceptions = node.createChildNode("ThermostatExceptions");
    for (int k = 0; k < integrator.getNumThermostatExceptions(); k++) {
        int p1, p2;
        double factor;
        integrator.getThermostatExceptionParameters(k, p1, p2, factor);
        exceptions.createChildNode("Exception").setIntProperty("p1", p1).setIntProperty("p2", p2).setDoubleProperty("factor", factor);
    }
}

void DPDPlugin::deserializeThermostatParameters(const XmlReader& xml, DPDThermostatIntegrator& integrator) {
    // Attributes added after the first format are optional; their defaults are the values
    // files without them ran with.
    integrator.setConstraintTolerance(xml.number("constraintTolerance", DEFAULT_CONSTRAINT_TOLERANCE));
    integrator.setRandomNumberSeed(xml.integer("randomSeed"));
    integrator.setIntegrationForceGroups(xml.integer("integrationForceGroups"));
    integrator.setInstabilityThreshold(xml.number("instabilityThreshold", 0.0));
    integrator.setShearRate(xml.number("shearRate", 0.0));
    integrator.setPressureTensorEnabled(xml.flag("pressureTensorEnabled", false));
    integrator.setDefaultWeightExponent(xml.number("defaultWeightExponent", 2.0));
    deserializeTypeTable(xml, integrator, "friction");
    if (xml.hasChild("WeightExponents"))
        for (const XmlReader& p : xml.child("WeightExponents").children())
            integrator.setTypePairWeightExponent(p.integer("index"), p.number("s"));
    integrator.setDefaultTransverseFriction(xml.number("defaultTransverseFriction", 0.0));
    integrator.setDefaultTransverseWeightExponent(xml.number("defaultTransverseWeightExponent", 2.0));
    if (xml.hasChild("TransverseFriction"))
        for (const XmlReader& p : xml.child("TransverseFriction").children())
            integrator.setTypePairTransverseFriction(p.integer("index"), p.number("friction"), p.number("s"));
    if (xml.hasChild("ThermostatExceptions"))
        for (const XmlReader& e : xml.child("ThermostatExceptions").children())
            integrator.addThermostatException(e.integer("p1"), e.integer("p2"), e.number("factor"));
}
