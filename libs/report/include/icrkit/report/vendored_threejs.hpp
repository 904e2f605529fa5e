#pragma once
/// \file
/// three.js as vendored at build time (scripts/vendor-threejs.sh): what
/// HtmlReportInput's viewer fields take. All empty when three.js could not
/// be vendored (no npm or network at build time); the report then says that
/// its 3D viewer is unavailable.

#include <string>

namespace icrkit::report {

std::string vendoredThreeVersion();         ///< e.g. "0.170.0"; empty when not vendored
std::string vendoredThreeModuleBase64();    ///< build/three.module.min.js, base64
std::string vendoredOrbitControlsBase64();  ///< examples/jsm/controls/OrbitControls.js, base64
std::string vendoredThreeLicense();         ///< three.js's LICENSE (MIT)

}  // namespace icrkit::report
