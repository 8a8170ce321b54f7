#pragma once
// Furniture clusters that are really several pieces joined by bridges of stray points.
//
// Stereo smears depth across an object's silhouette (pixels of the surface behind take
// ranges between the two) and reports stray ranges on plain surfaces; the points of
// both hang between pieces of furniture standing a hand's width apart, which then link
// into one voxel cluster and would be fitted as one box. The bridges are narrow in plan,
// the pieces are not where their tops, seen from the rig above them, fill their
// footprints. So the cluster's footprint (one cell per voxel column) is shrunk by neck_m:
// what remains falls apart into one solid core per such piece. Every column within
// reach_m of a core goes to the core nearest to it along the footprint; the columns out
// of every core's reach (a piece without a core of its own, as a loudspeaker seen only
// from the front, hanging on by a bridge; or the sparse far end of a large object) form
// pieces of their own, which the caller joins again where they are one object.
// A cluster without a core (a piece seen only from the side, or sparse and far) is left
// as it is.
#include <cstdint>
#include <vector>

#include "voxel_grid.h"

namespace room_reverb::core::layout {

struct ClusterSplitParams {
  double neck_m = 0.1;             // the footprint shrinks by this each way: bridges up
                                   // to twice as wide are cut
  double min_core_area_m2 = 0.08;  // a smaller core is not a piece: rows of points on a
                                   // top seen at a slant leave small cores between gaps
  double reach_m = 0.3;            // how far beyond its core a piece reaches
};

// The clusters (voxel indices into grid.voxels()) split into their pieces as above;
// `link_voxels` is how the clusters were linked (see connectedVoxelClusters), which
// links the columns out of reach into pieces.
std::vector<std::vector<std::uint32_t>> splitClustersAtNecks(const VoxelGrid& grid,
                                                            const std::vector<std::vector<std::uint32_t>>& clusters,
                                                            int link_voxels, const ClusterSplitParams& params);

}  // namespace room_reverb::core::layout
