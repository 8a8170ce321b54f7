#pragma once
// The scattering a surface adds by its finite size: a wall a few wavelengths across does
// not reflect a long wave as a mirror would; the specular share falls at low frequencies
// and near grazing, and what it loses is diffracted at the edges into other directions.
// Rindel's strip model ("Attenuation of sound reflections due to diffraction", Nordic
// Acoustical Meeting 1986): for a surface of width a seen at incidence angle theta, with
// characteristic distance a* = 2 d1 d2 / (d1 + d2) (d1, d2 from the source and to the
// receiver), the reflection is specular above f_g = c a* / (2 (a cos theta)^2) and its
// energy falls as f / f_g below. Christensen and Rindel (Forum Acusticum 2005) turn the
// lost share into a scattering coefficient, s_d = 1 - K, combined with the material's
// own as 1 - (1 - s)(1 - s_d): the reflection-based scattering of ODEON. No parameter is
// fitted; everything comes from the mesh and the frequency.
//
// A surface here is a connected piece of coplanar triangles, whatever their materials
// (a window in a wall diffracts at the wall's edges, not at the glass's), taken as the
// rectangle of the same area along its principal axes. ODEON also shortens the width for
// a reflection point near an edge; this model takes the whole width wherever the ray
// lands.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/triangle_mesh.h"

namespace room_reverb::core {

struct SurfaceExtent {
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();  // in-plane principal axes, unit
  Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();
  double width_u_m = 0.0;  // the equivalent rectangle: width_u * width_v = area,
  double width_v_m = 0.0;  // width_u / width_v the extents' ratio along the axes
  double area_m2 = 0.0;
};

// The surfaces of `mesh`: triangles of one plane (`triangle_plane`, per triangle) that
// share a vertex position (within 1 mm) are one surface. `triangle_patch` gets each
// triangle's index into the result.
std::vector<SurfaceExtent> surfaceExtents(const TriangleMesh& mesh, const std::vector<std::size_t>& triangle_plane,
                                         std::vector<std::size_t>& triangle_patch);

// 2 d1 d2 / (d1 + d2): the distance that sets the Fresnel zone of a reflection.
double characteristicDistance(double incoming_m, double outgoing_m);

// Rindel's specular energy share of a reflection off `patch` along `incident` (unit, the
// ray's direction), at `frequency_hz`: per axis, with the width as the incident wave
// sees it (a sqrt(1 - (d . axis)^2), i.e. a cos theta in the plane of incidence),
// min(1, f / f_g); the product over the two axes. In (0, 1].
double specularShare(const SurfaceExtent& patch, const Eigen::Vector3d& incident, double characteristic_distance_m,
                     double frequency_hz, double speed_of_sound_m_s);

// Per band (at each band's centre: the octaves', or a third-octave view's,
// AcousticScene::bandCentresHz): the material's scattering with the surface's diffraction
// added, 1 - (1 - s) K.
OctaveBandValues withDiffractionScattering(const OctaveBandValues& material_scattering, const SurfaceExtent& patch,
                                           const Eigen::Vector3d& incident, double characteristic_distance_m,
                                           double speed_of_sound_m_s,
                                           const OctaveBandValues& band_centres_hz = octaveCentresHz());

}  // namespace room_reverb::core
