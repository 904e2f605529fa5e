// PointCloud and TriangleMesh as thin Python objects: positions, normals and
// faces are NumPy views onto the C++ arrays (no copies); named per-element
// attributes come out as float64 copies (their C++ storage is a double per
// value too, but a dict of views would dangle when an attribute is replaced).

#include "arrays.hpp"

#include <icrkit/core/attributes.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace icrkit::python {
namespace {

py::dict attributesOf(const AttributeSet& attributes) {
  py::dict out;
  for (const Attribute& a : attributes) {
    py::array_t<double> values(static_cast<py::ssize_t>(a.values.size()));
    std::copy(a.values.begin(), a.values.end(), values.mutable_data());
    out[py::str(a.name)] = values;
  }
  return out;
}

void setAttribute(AttributeSet& attributes, std::size_t count, const std::string& name, const py::handle& values) {
  const py::array_t<double, py::array::c_style | py::array::forcecast> a = py::array_t<double>::ensure(values);
  if (!a || a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != count)
    throw py::value_error("attribute '" + name + "': expected a 1-D array of " + std::to_string(count) + " values");
  std::vector<double> v(a.data(), a.data() + a.shape(0));
  attributes.add(name, ScalarType::Float32, std::move(v));
}

}  // namespace

PointCloud cloudFromPython(const py::handle& points, const py::handle& normals) {
  PointCloud cloud;
  cloud.positions = toVectors(points, "points");
  if (!normals.is_none()) {
    cloud.normals = toVectors(normals, "normals");
    if (cloud.normals.size() != cloud.positions.size())
      throw py::value_error("normals: expected one per point (" + std::to_string(cloud.positions.size()) + "), got " +
                            std::to_string(cloud.normals.size()));
  }
  return cloud;
}

void bindGeometry(py::module_& m) {
  py::class_<PointCloud>(m, "PointCloud",
                         "Points (metres), optional unit normals and named per-point attributes. `points` and "
                         "`normals` are (N, 3) float64 views onto the C++ arrays.")
      .def(py::init([](const py::handle& points, const py::handle& normals) { return cloudFromPython(points, normals); }),
           py::arg("points"), py::arg("normals") = py::none())
      .def_property_readonly("points", [](py::object self) { return viewOf(self.cast<PointCloud&>().positions, self); })
      .def_property_readonly("normals",
                             [](py::object self) -> py::object {
                               PointCloud& c = self.cast<PointCloud&>();
                               if (!c.hasNormals()) return py::none();
                               return viewOf(c.normals, self);
                             })
      .def_property_readonly("attributes", [](const PointCloud& c) { return attributesOf(c.attributes); },
                             "dict name -> float64 array (a copy)")
      .def("set_attribute",
           [](PointCloud& c, const std::string& name, const py::handle& values) {
             setAttribute(c.attributes, c.size(), name, values);
           },
           py::arg("name"), py::arg("values"))
      .def("__len__", &PointCloud::size)
      .def("__repr__", [](const PointCloud& c) { return "<icrkit.PointCloud with " + std::to_string(c.size()) + " points>"; });

  py::class_<TriangleMesh>(m, "TriangleMesh",
                           "Vertices (a PointCloud: positions, normals, attributes) and triangles (M, 3) int32, "
                           "counter-clockwise seen from outside. Arrays are views onto the C++ data.")
      .def(py::init([](const py::handle& vertices, const py::handle& faces, const py::handle& normals) {
             TriangleMesh mesh;
             mesh.vertices = cloudFromPython(vertices, normals);
             const py::array_t<int, py::array::c_style> f = py::array_t<int, py::array::c_style>::ensure(faces);
             if (!f || f.ndim() != 2 || f.shape(1) != 3)
               throw py::value_error("faces: expected an integer array of shape (M, 3)");
             mesh.faces.resize(static_cast<std::size_t>(f.shape(0)));
             for (std::size_t i = 0; i < mesh.faces.size(); ++i)
               mesh.faces[i] = Triangle(f.data()[3 * i], f.data()[3 * i + 1], f.data()[3 * i + 2]);
             try {
               mesh.validate();
             } catch (const std::invalid_argument& e) {
               throw py::value_error(std::string("mesh: ") + e.what());
             }
             return mesh;
           }),
           py::arg("vertices"), py::arg("faces"), py::arg("normals") = py::none())
      .def_property_readonly("vertices",
                             [](py::object self) { return viewOf(self.cast<TriangleMesh&>().vertices.positions, self); })
      .def_property_readonly("normals",
                             [](py::object self) -> py::object {
                               TriangleMesh& mesh = self.cast<TriangleMesh&>();
                               if (!mesh.vertices.hasNormals()) return py::none();
                               return viewOf(mesh.vertices.normals, self);
                             })
      .def_property_readonly("faces",
                             [](py::object self) {
                               auto& faces = self.cast<TriangleMesh&>().faces;
                               static_assert(sizeof(Triangle) == 3 * sizeof(int), "Triangle must be three packed ints");
                               return py::array_t<int>({static_cast<py::ssize_t>(faces.size()), py::ssize_t{3}},
                                                       {static_cast<py::ssize_t>(sizeof(Triangle)),
                                                        static_cast<py::ssize_t>(sizeof(int))},
                                                       faces.empty() ? nullptr : faces.front().data(), self);
                             })
      .def_property_readonly("attributes", [](const TriangleMesh& m) { return attributesOf(m.vertices.attributes); },
                             "dict name -> float64 array of per-vertex values (a copy)")
      .def("set_attribute",
           [](TriangleMesh& mesh, const std::string& name, const py::handle& values) {
             setAttribute(mesh.vertices.attributes, mesh.vertexCount(), name, values);
           },
           py::arg("name"), py::arg("values"))
      .def("__repr__", [](const TriangleMesh& mesh) {
        return "<icrkit.TriangleMesh with " + std::to_string(mesh.vertexCount()) + " vertices and " +
               std::to_string(mesh.faceCount()) + " faces>";
      });

  m.def("read_mesh", &io::readTriangleMesh, py::arg("path"), py::call_guard<py::gil_scoped_release>(),
        "Reads a mesh (PLY, OBJ; PCD and XYZ give a mesh without faces; docs/formats.md). ValueError naming the file, line or element on bad input.");
  m.def("read_point_cloud", &io::readPointCloud, py::arg("path"), py::call_guard<py::gil_scoped_release>(),
        "Reads a point cloud (PLY, PCD, XYZ, OBJ vertices; docs/formats.md).");
  m.def("write_mesh", [](const std::string& path, const TriangleMesh& mesh) { io::writeTriangleMesh(path, mesh); },
        py::arg("path"), py::arg("mesh"), py::call_guard<py::gil_scoped_release>(),
        "Writes a mesh atomically (temporary file, then rename); the format follows the extension.");
  m.def("write_point_cloud", [](const std::string& path, const PointCloud& cloud) { io::writePointCloud(path, cloud); },
        py::arg("path"), py::arg("cloud"), py::call_guard<py::gil_scoped_release>());
}

}  // namespace icrkit::python
