// yarnvox._yarnvox: what the Python package (python/yarnvox/__init__.py) is
// built on. Garments as arrays, the command line's `gen` and `voxelize` run
// in this process, and a .vdb's grids as arrays.
#include "bcc.h"
#include "cli/embedded_command.h"
#include "command_run.h"
#include "garment/cross_section.h"
#include "pipeline/yarn_radius.h"
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

/// The yarn radius a voxelize run would use, as it chooses it.
py::dict chooseRadius(const std::string& path, double yarnRadius, const std::string& crossSection) {
    YarnRadiusChoice c;
    {
        py::gil_scoped_release released;
        const Garment g = readBcc(path);
        c = chooseYarnRadius(yarnRadius, makeCrossSection(crossSection), g, path);
    }
    py::dict out;
    out["radius"] = c.radius;
    out["source"] = c.source;
    out["description"] = c.description;
    return out;
}

} // namespace
} // namespace yv::python

PYBIND11_MODULE(_yarnvox, m) {
    using namespace yv::python;
    m.doc() = "yarnvox's C++ layers for the yarnvox package; use the package's functions";
    registerExceptions(m);
    m.def("run_command", &runCommand, py::arg("words"), py::arg("progress") = py::none(),
          "Runs `gen` or `voxelize` with command-line words; returns one report a voxelized garment");
    m.def("option_names", &yv::embeddedCommandOptions, py::arg("command"),
          "(name, is_flag) for each long option of `gen` or `voxelize`");
    m.def("read_bcc", &readGarment, py::arg("path"));
    m.def("yarn_radius", &chooseRadius, py::arg("path"), py::arg("yarn_radius") = 0.0,
          py::arg("cross_section") = "fibers");
    m.def("read_dense", &readDenseVolume, py::arg("path"), py::arg("level") = 0, py::arg("box") = py::none());
    m.def("read_sparse", &readSparseVolume, py::arg("path"), py::arg("level") = 0);
}
