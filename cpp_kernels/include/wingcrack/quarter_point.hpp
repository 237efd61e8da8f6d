#pragma once
// Quarter-point (Barsoum 1977) crack-tip elements and the validity check of
// the P2 isoparametric map (paper section 3.1).
#include <Eigen/Core>

#include "wingcrack/face_split.hpp"

namespace wingcrack {

// Returns a copy of x where the mid-edge node of every cell edge with exactly
// one end at a tip node sits at 1/4 of the edge length from the tip, on the
// straight tip-corner chord. That makes the P2 map reproduce the 1/sqrt(r)
// strain singularity along the edges. Edges joining two tips are left alone.
Coords2 quarter_points(const Coords2& x, const P2Cells& cells, const IndexVector& tip_nodes);

// Minimum over the 6 interior points of the degree-4 Dunavant rule of
// det J of the P2 isoparametric map of each cell. Equals 2 * area for a
// straight-sided cell with mid-edge nodes at the midpoints; stays > 0 for a
// valid quarter-point cell (det J vanishes only at the tip vertex itself).
Eigen::VectorXd min_jacobian(const Coords2& x, const P2Cells& cells);

}  // namespace wingcrack
