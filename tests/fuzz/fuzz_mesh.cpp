// Fuzz target of mesh files and body validation (see tests/fuzz/README.md). Byte 0 chooses the
// format (bits 0-1: OFF, PLY, OBJ, STL, by the file extension) and whether the opt-in repair
// runs (bit 2, with hole filling when bit 3 is set); the rest is the file's content, written to
// a temporary file and read with readMesh(), as `steady sweep` reads its body. A mesh read is
// validated as a sweep body (Body), and repaired and validated again when asked.
//
// Checks, beyond "a result or a steady::Error": a mesh read has at least one triangle and only
// finite coordinates and indices in range (readMesh's promise); a Body keeps the mesh as given
// and has a positive volume; a repaired mesh has indices in range.
#include "fuzz_check.hpp"

#include <steady/io/mesh.hpp>
#include <steady/sweep/body.hpp>
#include <steady/sweep/repair.hpp>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

bool indicesInRange(const std::vector<Eigen::Vector3d>& V, const std::vector<std::array<int, 3>>& F) {
  for (const auto& f : F)
    for (const int v : f)
      if (v < 0 || static_cast<std::size_t>(v) >= V.size()) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExt[4] = {".off", ".ply", ".obj", ".stl"};
  const std::string path = "/tmp/steady-fuzz-mesh-" + std::to_string(::getpid()) + kExt[data[0] & 3];
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
    FUZZ_CHECK(out.good(), "cannot write the temporary input file");
  }
  steady::io::TriangleMesh mesh;
  const bool read = steady::fuzz::typedOrOk("readMesh", [&] { mesh = steady::io::readMesh(path); });
  std::remove(path.c_str());
  if (!read) return 0;
  FUZZ_CHECK(!mesh.faces.empty(), "readMesh returned a mesh without triangles");
  for (const auto& v : mesh.vertices) FUZZ_CHECK(v.allFinite(), "readMesh returned a non-finite coordinate");
  FUZZ_CHECK(indicesInRange(mesh.vertices, mesh.faces), "readMesh returned a face index out of range");

  steady::fuzz::typedOrOk("Body", [&] {
    const steady::sweep::Body body(mesh.vertices, mesh.faces);
    FUZZ_CHECK(body.faces() == mesh.faces && body.vertices() == mesh.vertices, "Body changed the mesh");
    FUZZ_CHECK(body.signedVolume() > 0, "a valid body without positive volume");
  });
  if (!(data[0] & 4)) return 0;
  steady::sweep::RepairOptions options;
  options.fill_holes = (data[0] & 8) != 0;
  steady::fuzz::typedOrOk("repairMesh", [&] {
    steady::sweep::repairMesh(mesh.vertices, mesh.faces, options);
    FUZZ_CHECK(indicesInRange(mesh.vertices, mesh.faces), "repairMesh returned a face index out of range");
    steady::fuzz::typedOrOk("Body after repair", [&] { steady::sweep::Body body(mesh.vertices, mesh.faces); });
  });
  return 0;
}
