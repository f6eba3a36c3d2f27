#include "openmmdpd/OpenMMVersionCheck.h"
#include "openmm/Platform.h"
#include <gtest/gtest.h>

using namespace DPDPlugin;

TEST(OpenMMVersion, PluginsLoadOnlyIntoTheMajorMinorBuiltAgainst) {
    EXPECT_EQ(openmmVersionMismatch("8.5", "8.5.2"), "");
    EXPECT_EQ(openmmVersionMismatch("7.7", "7.7"), "");
    // 8.4 changed the layout of the platform data our kernels read.
    const std::string why = openmmVersionMismatch("8.3", "8.4.0");
    EXPECT_NE(why.find("built against OpenMM 8.3 but loaded into OpenMM 8.4.0"), std::string::npos) << why;
    EXPECT_NE(why.find("rebuild openmm-dpd against OpenMM 8.4"), std::string::npos) << why;
    EXPECT_NE(openmmVersionMismatch("8.1", "8.10"), "");
    EXPECT_NE(openmmVersionMismatch("7.7", "8.5.2"), "");
}

TEST(OpenMMVersion, TheRunningOpenMMIsTheOneBuiltAgainst) {
    EXPECT_EQ(openmmVersionMismatch(OPENMMDPD_OPENMM_VERSION, OpenMM::Platform::getOpenMMVersion()), "");
    EXPECT_TRUE(pluginMatchesRunningOpenMM("test"));
}
