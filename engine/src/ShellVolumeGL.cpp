#include <atmoglobe/engine/ShellVolumeGL.h>

#include "LoaderGL.h"

#include <sstream>

namespace atmoglobe::engine {

ShellVolumeGL::ShellVolumeGL(const volume::UniformShell& shell)
    : shell_(shell), centreEcef_(globe::geodeticToEcef(shell.centre)), sampler_(shell) {
  // The grid: one box around the outer sphere, in the centre's ENU frame.
  const glm::dvec3 r(shell.outerRadiusMeters);
  occupancy_ = OccupancyGridGL(
      volume::buildOccupancyGrid(centreEcef_, globe::enuAxes(shell.centre.latDeg, shell.centre.lonDeg),
                                 {volume::OccupancyBox{-r, r, static_cast<float>(shell.value)}}, glm::ivec3(8, 8, 8)));
}

void ShellVolumeGL::setSamplerUniforms(const SamplerBindingGL& b) const {
  glUniform3f((*b.uniforms)(b.prefix + "shellRadii"), static_cast<float>(shell_.innerRadiusMeters),
              static_cast<float>(shell_.outerRadiusMeters), static_cast<float>(shell_.value));
}

std::string ShellVolumeGL::description() const { return volume::UniformShellSampler(shell_).description(); }

}  // namespace atmoglobe::engine
