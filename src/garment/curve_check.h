// Garments as real files give them: repeated control points, closed curves
// whose last point repeats the first, a closed flag that draws a chord across
// the garment. What can be repaired without changing the yarn is repaired and
// counted; what cannot be a curve is refused, naming the file, curve and point.
#pragma once

#include "garment/garment.h"

#include <cstddef>
#include <string>
#include <vector>

namespace yv {

struct CurveCheckReport {
    std::size_t droppedSpans = 0;        ///< zero-length spans removed (a point repeating its predecessor)
    std::size_t droppedClosingSpans = 0; ///< of them: a closed curve's last point repeating its first
    std::size_t cusps = 0;               ///< knots where a curve turns straight back (no tangent), voxelized as cusps
    std::vector<std::string> warnings;   ///< one line each, without "warning: "

    /// One line for stderr saying what was dropped ("" when nothing was).
    std::string droppedText(const std::string& name) const;
};

/// Checks and tidies a garment read from file `name` before slicing.
/// Catmull-Rom and polyline curves lose their zero-length spans (a point equal
/// to the one before it, and a closed curve's last point equal to its first;
/// for Bezier curves only the latter). Throws yv::Error, naming `name`, the
/// curve and the point, for what cannot be a curve: all points in one place,
/// a segment that does not move, a B-spline or Bezier curve with a point count
/// its type cannot use. Warns, in one line for the whole garment, about knots
/// where a curve turns straight back (its neighbours coincide, so it has no
/// tangent there): real knits have them, renderers draw them, and the slicer
/// takes each side's own tangent there (knotDirection). Warns about a span far
/// longer than the rest of its curve.
CurveCheckReport checkCurves(Garment& garment, const std::string& name);

} // namespace yv
