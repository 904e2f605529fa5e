#include <icrkit/core/triangle_mesh.hpp>

#include <stdexcept>
#include <string>

namespace icrkit {

void TriangleMesh::validate() const {
  vertices.validate();
  const long n = static_cast<long>(vertices.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k)
      if (faces[f][k] < 0 || faces[f][k] >= n)
        throw std::invalid_argument("face " + std::to_string(f) + " refers to vertex " + std::to_string(faces[f][k]) +
                                    ", expected 0.." + std::to_string(n - 1));
}

}  // namespace icrkit
