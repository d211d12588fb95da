// yarnvox._yarnvox: the arrays of the Python package
// (python/yarnvox/__init__.py): a garment's curves, its yarn radius estimate,
// and a .vdb's grids. The package runs `gen` and `voxelize` through the
// command line itself.
#include "bcc.h"
#include "core/error.h"
#include "garment/radius_estimate.h"
#include "volume_arrays.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace yv::python {
namespace {

const char* curveTypeName(CurveType t) {
    switch (t) {
    case CurveType::Polyline: return "polyline";
    case CurveType::BSpline: return "bspline";
    case CurveType::Bezier: return "bezier";
    default: return "catmull-rom";
    }
}

/// A garment file as a dict: each yarn's control points as an (n, 3) array.
py::dict readGarment(const std::string& path) {
    Garment g;
    {
        py::gil_scoped_release released;
        g = readBcc(path);
    }
    py::list yarns, closed;
    for (const Yarn& y : g.yarns) {
        py::array_t<double> points({py::ssize_t(y.points.size()), py::ssize_t(3)});
        auto w = points.mutable_unchecked<2>();
        for (std::size_t i = 0; i < y.points.size(); ++i)
            for (int k = 0; k < 3; ++k) w(py::ssize_t(i), k) = y.points[i][k];
        yarns.append(points);
        closed.append(y.closed);
    }
    py::dict out;
    out["yarns"] = yarns;
    out["closed"] = closed;
    out["curve_type"] = curveTypeName(g.curveType);
    out["yarn_radius"] = g.yarnRadius;
    out["control_points"] = g.controlPointCount();
    out["segments"] = g.segmentCount();
    return out;
}

/// The yarn radius voxelize estimates from a garment that records none
/// (estimateYarnRadius: half the median distance where yarns touch).
py::dict estimateRadius(const std::string& path) {
    RadiusEstimate e;
    {
        py::gil_scoped_release released;
        e = estimateYarnRadius(readBcc(path));
    }
    py::dict out;
    out["radius"] = e.radius;
    out["samples"] = e.samples;
    out["contacts"] = e.contacts;
    return out;
}

} // namespace
} // namespace yv::python

PYBIND11_MODULE(_yarnvox, m) {
    using namespace yv::python;
    m.doc() = "yarnvox's C++ layers for the yarnvox package; use the package's functions";
    // yarnvox's errors (a damaged file, a missing grid) as the package's Error, message unchanged.
    static py::exception<yv::Error> error(m, "Error", PyExc_RuntimeError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const yv::Error& e) {
            error(e.what());
        }
    });
    m.def("read_bcc", &readGarment, py::arg("path"));
    m.def("estimate_yarn_radius", &estimateRadius, py::arg("path"));
    m.def("read_dense", &readDenseVolume, py::arg("path"), py::arg("level") = 0, py::arg("box") = py::none());
    m.def("read_sparse", &readSparseVolume, py::arg("path"), py::arg("level") = 0);
    m.def("read_metadata", &readVolumeMetadata, py::arg("path"));
}
