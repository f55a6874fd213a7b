// steady::io meshes: round trips in every format, polygon files, read errors, atomic writes.

#include <steady/io/mesh.hpp>

#include <steady/core/error.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using steady::Error;
using steady::ErrorCode;
using steady::io::MeshWriteOptions;
using steady::io::TriangleMesh;

namespace {

// A fresh directory per test, removed afterwards.
class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "steady_io_test_XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    return names;
  }
  void writeText(const std::string& name, const std::string& text) const {
    std::ofstream out(path(name), std::ios::binary);
    out << text;
  }
  static std::string readText(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  fs::path dir_;
};

// A closed, outward-oriented triangulated box with coordinates that are not exact in binary
// (0.1, 1/3), a large and a small magnitude; vertices listed in order of first use by the
// faces, so that STL's merging of equal corners gives back the same order.
TriangleMesh awkwardBox() {
  const double x0 = -0.1, x1 = 1.0 / 3.0, y0 = -2.5e6, y1 = 1.25e6, z0 = 1e-5, z1 = 7.75;
  TriangleMesh m;
  m.vertices = {{x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0},
                {x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}};
  m.faces = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {0, 3, 5}, {0, 5, 4},
             {2, 1, 7}, {2, 7, 6}, {3, 2, 6}, {3, 6, 5}, {0, 4, 7}, {0, 7, 1}};
  return m;
}

// STL holds coordinates as 32-bit floats: agreement to float precision there. OFF, OBJ and PLY
// are read in double: every coordinate bit for bit (OpenMesh 9's readers alone round them to
// float).
void expectSameMesh(const TriangleMesh& got, const TriangleMesh& want, bool exact) {
  ASSERT_EQ(got.vertices.size(), want.vertices.size());
  ASSERT_EQ(got.faces.size(), want.faces.size());
  for (std::size_t i = 0; i < want.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double g = got.vertices[i](k), w = want.vertices[i](k);
      if (exact)
        EXPECT_EQ(g, w) << "vertex " << i << " coordinate " << k;
      else
        EXPECT_NEAR(g, w, 1.2e-7 * std::abs(w) + 1e-300) << "vertex " << i << " coordinate " << k;
    }
  for (std::size_t i = 0; i < want.faces.size(); ++i) EXPECT_EQ(got.faces[i], want.faces[i]) << "face " << i;
}

struct Case {
  const char* ext;
  bool binary;
};

class MeshRoundTrip : public MeshIo, public ::testing::WithParamInterface<Case> {};

TEST_P(MeshRoundTrip, ReadsBackWhatWasWritten) {
  const Case c = GetParam();
  const TriangleMesh box = awkwardBox();
  const std::string file = path(std::string("box.") + c.ext);
  MeshWriteOptions options;
  options.binary = c.binary;
  steady::io::writeMesh(file, box, options);
  EXPECT_EQ(entries(), std::vector<std::string>{std::string("box.") + c.ext}) << "no temporary file is left";
  const TriangleMesh back = steady::io::readMesh(file);
  expectSameMesh(back, box, std::string(c.ext) != "stl");  // STL too: corners merged in order of first appearance

  const std::string text = readText(file);
  if (std::string(c.ext) == "stl" && c.binary) {
    EXPECT_EQ(text.size(), 84u + 50u * box.faces.size());
    EXPECT_NE(text.rfind("solid", 0), 0u) << "a binary STL header must not start with 'solid'";
  }
  if (std::string(c.ext) == "ply") {
    EXPECT_NE(text.find(c.binary ? "format binary_little_endian 1.0" : "format ascii 1.0"), std::string::npos);
  }
}

TEST_F(MeshIo, TextFormatsKeepEveryDigit) {
  // What steady writes is exact (the shortest decimal that reads back to the same double).
  for (const char* name : {"box.off", "box.obj", "box.ply", "box.stl"}) {
    steady::io::writeMesh(path(name), awkwardBox());
    const std::string text = readText(path(name));
    EXPECT_NE(text.find("0.3333333333333333"), std::string::npos) << name;
    EXPECT_NE(text.find("-2500000"), std::string::npos) << name;
    EXPECT_NE(text.find("1e-05"), std::string::npos) << name;
  }
}

// Files written by hand are read in double too: 0.1 and 1e-300 exactly, with extra numbers after
// x y z (colours, w) and extra vertex properties ignored, PLY in either byte order. (A text
// coordinate is the double nearest its decimal, whatever type the PLY header declares.)
TEST_F(MeshIo, HandWrittenFilesAreReadInDouble) {
  const std::vector<Eigen::Vector3d> want = {{0.1, 0.2, 0.3}, {1e-300, -7, 2.5}, {1, 1, 1}, {0, 1, 0}};
  writeText("hand.off", "OFF\n4 1 0\n0.1 0.2 0.3 1 0 0\n1e-300 -7 2.5\n1 1 1\n0 1 0\n4 0 1 2 3\n");
  writeText("hand.obj", "# a quad\nv 0.1 0.2 0.3 1.0\nv\t1e-300 -7 2.5\nvn 0 0 1\nv 1 1 1 0.5 0.5 0.5\nv 0 1 0\nf 1 2 3 4\n");
  writeText("hand_ascii.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty uchar red\n"
                              "property double y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                              "end_header\n0.1 9 0.2 0.3\n1e-300 9 -7 2.5\n1 9 1 1\n0 9 1 0\n4 0 1 2 3\n");
  {  // big-endian binary doubles, with a uchar between x and y
    std::string ply = "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\nproperty uchar red\n"
                      "property double y\nproperty double z\nelement face 1\nproperty list uchar int vertex_indices\n"
                      "end_header\n";
    auto big = [&](const void* p, int n) {
      for (int j = n - 1; j >= 0; --j) ply += static_cast<const char*>(p)[j];  // the test host is little endian
    };
    for (const Eigen::Vector3d& v : want) {
      big(&v.x(), 8);
      ply += '\x09';
      big(&v.y(), 8);
      big(&v.z(), 8);
    }
    ply += '\x04';
    for (const std::int32_t i : {0, 1, 2, 3}) big(&i, 4);
    writeText("hand_big.ply", ply);
  }
  for (const char* name : {"hand.off", "hand.obj", "hand_ascii.ply", "hand_big.ply"}) {
    const TriangleMesh m = steady::io::readMesh(path(name));
    ASSERT_EQ(m.vertices.size(), 4u) << name;
    for (std::size_t i = 0; i < 4; ++i)
      EXPECT_TRUE(m.vertices[i] == want[i]) << name << " vertex " << i << ": " << m.vertices[i].transpose();
    EXPECT_EQ(m.faces.size(), 2u) << name;
  }
}

TEST_F(MeshIo, BinaryPlyHoldsExactDoubles) {
  const TriangleMesh box = awkwardBox();
  steady::io::writeMesh(path("box.ply"), box, MeshWriteOptions{true});
  const std::string text = readText(path("box.ply"));
  const std::string end = "end_header\n";
  const std::size_t start = text.find(end) + end.size();
  ASSERT_EQ(text.size(), start + box.vertices.size() * 24 + box.faces.size() * 13);
  for (std::size_t i = 0; i < box.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      double x = 0;
      std::memcpy(&x, text.data() + start + 24 * i + 8 * static_cast<std::size_t>(k), 8);  // the test host is little endian
      EXPECT_EQ(x, box.vertices[i](k));
    }
}

INSTANTIATE_TEST_SUITE_P(AllFormats, MeshRoundTrip,
                         ::testing::Values(Case{"off", false}, Case{"obj", false}, Case{"ply", false}, Case{"ply", true},
                                           Case{"stl", false}, Case{"stl", true}),
                         [](const ::testing::TestParamInfo<Case>& p) {
                           return std::string(p.param.ext) + (p.param.binary ? "_binary" : "_text");
                         });

TEST_F(MeshIo, UpperCaseExtensionsAreKnown) {
  steady::io::writeMesh(path("BOX.OFF"), awkwardBox());
  expectSameMesh(steady::io::readMesh(path("BOX.OFF")), awkwardBox(), true);
  EXPECT_EQ(steady::io::meshFormatOf("a/b.Ply"), steady::io::MeshFormat::Ply);
}

TEST_F(MeshIo, PolygonsBecomeTriangleFans) {
  writeText("poly.off",
            "OFF\n6 2 0\n0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 1 0\n0 0 1\n5 0 1 2 3 4\n3 0 4 5\n");
  const TriangleMesh m = steady::io::readMesh(path("poly.off"));
  ASSERT_EQ(m.vertices.size(), 6u);
  const std::vector<std::array<int, 3>> want = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
  EXPECT_EQ(m.faces, want);
}

TEST_F(MeshIo, ObjWithTextureAndNormalIndicesAndQuads) {
  writeText("q.obj",
            "# a unit square as one quad, and a triangle\n"
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
            "f 1/1/1 2/2/1 3/3/1 4/4/1\nf 1//1 3//1 4//1\n");
  const TriangleMesh m = steady::io::readMesh(path("q.obj"));
  ASSERT_EQ(m.vertices.size(), 4u);
  const std::vector<std::array<int, 3>> want = {{0, 1, 2}, {0, 2, 3}, {0, 2, 3}};
  EXPECT_EQ(m.faces, want);
}

TEST_F(MeshIo, NonManifoldFacesAreKeptAsTheyAre) {
  // Three triangles on one edge: OpenMesh's half-edge mesh would split them, steady keeps them.
  writeText("fan.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  const TriangleMesh m = steady::io::readMesh(path("fan.off"));
  EXPECT_EQ(m.vertices.size(), 5u);
  EXPECT_EQ(m.faces.size(), 3u);
}

TEST_F(MeshIo, BundledMeshesAreClosedAndOutward) {
  for (const char* name : {"tetrahedron.off", "box.off"}) {
    const TriangleMesh m = steady::io::readMesh(std::string(STEADY_DATA_DIR) + "/meshes/" + name);
    // Closed and outward: the divergence theorem gives a positive volume, and every edge is
    // used once in each direction.
    double volume = 0;
    std::multiset<std::pair<int, int>> edges;
    for (const auto& f : m.faces) {
      volume += m.vertices[static_cast<std::size_t>(f[0])].dot(
                    m.vertices[static_cast<std::size_t>(f[1])].cross(m.vertices[static_cast<std::size_t>(f[2])])) / 6.0;
      for (int k = 0; k < 3; ++k) edges.insert({f[static_cast<std::size_t>(k)], f[static_cast<std::size_t>((k + 1) % 3)]});
    }
    EXPECT_GT(volume, 0) << name;
    for (const auto& e : edges) {
      EXPECT_EQ(edges.count(e), 1u) << name;
      EXPECT_EQ(edges.count({e.second, e.first}), 1u) << name;
    }
  }
}

// --- read errors ---

void expectError(const std::function<void()>& f, ErrorCode code, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    for (const auto& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << "'" << p << "' not in: " << e.what();
  }
}

TEST_F(MeshIo, ReadMissingFileIsIo) {
  expectError([&] { steady::io::readMesh(path("none.off")); }, ErrorCode::Io, {"none.off", "No such file"});
}

TEST_F(MeshIo, ReadDirectoryIsIo) {
  fs::create_directory(path("d.stl"));
  expectError([&] { steady::io::readMesh(path("d.stl")); }, ErrorCode::Io, {"d.stl", "directory"});
}

TEST_F(MeshIo, ReadUnknownExtensionIsInvalidFile) {
  writeText("m.xyz", "1 2 3\n");
  expectError([&] { steady::io::readMesh(path("m.xyz")); }, ErrorCode::InvalidFile, {"m.xyz", "'.xyz'", ".off, .ply, .obj and .stl"});
  expectError([&] { steady::io::readMesh(path("noext")); }, ErrorCode::InvalidFile, {"no file extension"});
}

TEST_F(MeshIo, ReadGarbageIsInvalidFile) {
  writeText("g.off", "this is not an OFF file\n");
  expectError([&] { steady::io::readMesh(path("g.off")); }, ErrorCode::InvalidFile, {"g.off", "OFF"});
  writeText("g.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n");
  expectError([&] { steady::io::readMesh(path("g.ply")); }, ErrorCode::InvalidFile, {"g.ply"});
  // A fourth token on the counts line shifted OpenMesh's reading (it reads tokens, not lines)
  // until a coordinate became a face of 2^32 - 1 corners.
  writeText("c.off", "OFF\n3 1 0-1 0.5\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expectError([&] { steady::io::readMesh(path("c.off")); }, ErrorCode::InvalidFile,
              {"c.off", "line 2: expected the counts 'vertices faces edges', got '3 1 0-1 0.5'"});
  writeText("v.off", "OFF3\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 2 3\n3 0 3 1\n");
  expectError([&] { steady::io::readMesh(path("v.off")); }, ErrorCode::InvalidFile,
              {"v.off", "line 1: the header 'OFF3' is neither OFF nor one of its variants"});
  // OpenMesh (built with assertions) aborted the process on a face it could not read.
  writeText("h.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf h 0 0\n");
  expectError([&] { steady::io::readMesh(path("h.obj")); }, ErrorCode::InvalidFile,
              {"h.obj", "line 4 ('f h 0 0') is not a face"});
  writeText("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1 2//2\n");
  expectError([&] { steady::io::readMesh(path("two.obj")); }, ErrorCode::InvalidFile, {"two.obj", "line 4"});
  writeText("ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2//1 -1\n");
  EXPECT_EQ(steady::io::readMesh(path("ok.obj")).faces.size(), 1u);
  writeText("g.obj", "hello world\n");
  expectError([&] { steady::io::readMesh(path("g.obj")); }, ErrorCode::InvalidFile, {"g.obj", "no triangle"});
  writeText("e.stl", "");
  expectError([&] { steady::io::readMesh(path("e.stl")); }, ErrorCode::InvalidFile, {"e.stl"});
}

// A PLY header without end_header made OpenMesh's reader run forever, its complaints filling
// the memory, and an element line without a count made it allocate without end (fuzz inputs,
// tests/fuzz/corpus/mesh/ply_*). Malformed header lines are refused before OpenMesh reads.
TEST_F(MeshIo, ReadPlyHeaderWithoutEndIsInvalidFile) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\n";
  writeText("open.ply", head + "end\x7fheader\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expectError([&] { steady::io::readMesh(path("open.ply")); }, ErrorCode::InvalidFile,
              {"open.ply", "header line 9 ('end?header') holds a byte that is not text"});
  // "element vertex4" without a count made OpenMesh add elements until the memory ran out.
  writeText("count.ply", "ply\nformat binary_little_endian 1.0\nelement vertex4\nproperty double x\nend_header\n");
  expectError([&] { steady::io::readMesh(path("count.ply")); }, ErrorCode::InvalidFile,
              {"count.ply", "header line 3 ('element vertex4') is not 'element <name> <count>'"});
  // A property type OpenMesh does not know made it complain forever.
  writeText("type.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                        "property double z\nelement face 1\nproperty list uchar int[ vertex_indices\nend_header\n");
  expectError([&] { steady::io::readMesh(path("type.ply")); }, ErrorCode::InvalidFile,
              {"type.ply", "header line 8 ('property list uchar int[ vertex_indices') is not"});
  // So did a format version other than 1.0.
  writeText("version.ply", "ply\nformat binary_little_endian \xff" "1.0\nelement vertex 3\nproperty double x\nend_header\n");
  expectError([&] { steady::io::readMesh(path("version.ply")); }, ErrorCode::InvalidFile,
              {"version.ply", "header line 2 ('format binary_little_endian ?1.0') holds a byte that is not text"});
  // A property before any element crashed OpenMesh (a segmentation fault).
  writeText("orphan.ply", "ply\nformat ascii 1.0\ncomment vertex 4\nproperty double x\nend_header\n");
  expectError([&] { steady::io::readMesh(path("orphan.ply")); }, ErrorCode::InvalidFile,
              {"orphan.ply", "header line 4 ('property double x') is a property before any element line"});
  writeText("version2.ply", "ply\nformat ascii 2.0\nelement vertex 3\nproperty double x\nend_header\n");
  expectError([&] { steady::io::readMesh(path("version2.ply")); }, ErrorCode::InvalidFile,
              {"version2.ply", "is not 'format ascii|binary_little_endian|binary_big_endian 1.0'"});
  writeText("cut.ply", head);
  expectError([&] { steady::io::readMesh(path("cut.ply")); }, ErrorCode::InvalidFile, {"cut.ply", "no 'end_header' line"});
  writeText("nohead.ply", "plx\n" + head + "end_header\n");
  expectError([&] { steady::io::readMesh(path("nohead.ply")); }, ErrorCode::InvalidFile, {"does not start with the line 'ply'"});
  // (comment and obj_info lines are header lines too)
  writeText("ok.ply", "ply\nformat ascii 1.0\ncomment made by hand\nobj_info x\n" + head.substr(21) +
                          "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(steady::io::readMesh(path("ok.ply")).faces.size(), 1u);
}

// Headers announcing far more than the file holds: OpenMesh's readers follow the count, not the
// file's end (an OFF variant with a garbage header was read as zeros until 3 GB: a fuzz input,
// tests/fuzz/corpus/mesh/off_garbage_count). Reading stops at half the file's size in elements.
TEST_F(MeshIo, ReadCountsBeyondTheFileSizeIsInvalidFile) {
  // (a binary OFF whose counts are the bytes of the text "4 4 0": about 4e8 each)
  writeText("many.off", "OFF BINARY\n4 4 0\n0 0 0\n");
  expectError([&] { steady::io::readMesh(path("many.off")); }, ErrorCode::InvalidFile,
              {"many.off", "than its size can hold (27 at most)", "corrupt header"});
}

TEST_F(MeshIo, ReadIndexOutOfRangeIsInvalidFile) {
  writeText("bad.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 7\n");
  expectError([&] { steady::io::readMesh(path("bad.off")); }, ErrorCode::InvalidFile,
              {"bad.off", "line 7: face 1: corner '7' is not a vertex index in 0..2"});
  writeText("bad.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
            "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 9 1\n");
  expectError([&] { steady::io::readMesh(path("bad.ply")); }, ErrorCode::InvalidFile, {"bad.ply", "face 1 refers to vertex 9"});
  writeText("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  expectError([&] { steady::io::readMesh(path("bad.obj")); }, ErrorCode::InvalidFile, {"bad.obj"});
}

TEST_F(MeshIo, ReadTruncatedFilesIsInvalidFile) {
  writeText("short.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n");
  expectError([&] { steady::io::readMesh(path("short.off")); }, ErrorCode::InvalidFile,
              {"short.off", "the file ends after 1 of the 2 faces it announces"});
  writeText("few.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n");
  expectError([&] { steady::io::readMesh(path("few.off")); }, ErrorCode::InvalidFile, {"after 2 of the 4 vertices"});
  writeText("nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
  expectError([&] { steady::io::readMesh(path("nan.off")); }, ErrorCode::InvalidFile, {"line 4: expected vertex 1 as three finite numbers"});

  steady::io::writeMesh(path("box.stl"), awkwardBox(), MeshWriteOptions{true});
  const std::string full = readText(path("box.stl"));
  writeText("cut.stl", full.substr(0, full.size() - 10));
  expectError([&] { steady::io::readMesh(path("cut.stl")); }, ErrorCode::InvalidFile,
              {"cut.stl", "announces 12 triangles (684 bytes) but it has 674 bytes"});
  steady::io::writeMesh(path("box.ply"), awkwardBox(), MeshWriteOptions{true});
  const std::string ply = readText(path("box.ply"));
  writeText("cut.ply", ply.substr(0, ply.size() - 20));
  expectError([&] { steady::io::readMesh(path("cut.ply")); }, ErrorCode::InvalidFile, {"cut.ply"});
}

// Text OFF is read by steady, a line per vertex and per face. OpenMesh 9 read a face's corners
// as tokens: a colour after a face's corners (which OFF allows) was taken for the next face,
// and a tetrahedron came back with 760 triangles, silently; other lines made it allocate
// gigabytes (tests/fuzz/corpus/mesh/off_vertex_line_shift). It also misread comments and counts
// on the header's line.
TEST_F(MeshIo, ReadTextOffLineByLine) {
  const std::vector<Eigen::Vector3d> corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<std::array<int, 3>> faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const auto expectTetrahedron = [&](const std::string& name, const std::string& text) {
    SCOPED_TRACE(name);
    writeText(name, text);
    const TriangleMesh m = steady::io::readMesh(path(name));
    EXPECT_EQ(m.vertices, corners);
    EXPECT_EQ(m.faces, faces);
  };
  expectTetrahedron("colour.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 255 0 0\n3 0 1 3 0.5 0.5 0.5 1\n"
                                  "3 0 3 2 7\n3 1 2 3\n");
  expectTetrahedron("header.off", "OFF 4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expectTetrahedron("comment.off", "# made by hand\nOFF\n\n4 4 # no edges\n0 0 0 # origin\n+1 0 0\n0 1.0 -0\n0 0 1e0\n"
                                   "3 0 2 1\n\n3 0 1 3\n3 0 3 2\n3 1 2 3 # last\nanything after the faces\n");
  expectTetrahedron("coff.off", "COFF\n4 4 0\n0 0 0 255 0 0 255\n1 0 0 1 1 1\n0 1 0 0.5 0.5 0.5 1\n0 0 1 9\n"
                                "3 0 2 1 1 0 0\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expectTetrahedron("stcnoff.off", "STCNOFF\n4 4 0\n0 0 0 0 0 1 1 1 1 1 0 0\n1 0 0 0 0 1 1 1 1 1 0 0\n"
                                   "0 1 0 0 0 1 1 1 1 1 0 0\n0 0 1 0 0 1 1 1 1 1 0 0\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");

  // (faces of fewer than three corners are skipped)
  writeText("short.off", "OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n0\n3 0 1 2\n");
  EXPECT_EQ(steady::io::readMesh(path("short.off")).faces, (std::vector<std::array<int, 3>>{{0, 1, 2}}));

  const std::string tetra = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  writeText("two.off", "OFF\n4 2 0\n" + tetra + "3 0 2 1 4 0 1 3 2\n3 0 3 2\n");
  expectError([&] { steady::io::readMesh(path("two.off")); }, ErrorCode::InvalidFile,
              {"two.off", "line 7: face 0 has 5 values after it, more than the 4", "on its own line"});
  writeText("word.off", "OFF\n4 1 0\n0 0 0 red\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n");
  expectError([&] { steady::io::readMesh(path("word.off")); }, ErrorCode::InvalidFile,
              {"word.off", "line 3: vertex 0: 'red' after it is not a number"});
  writeText("split.off", "OFF\n4 1 0\n" + tetra + "3 0 2\n1\n");
  expectError([&] { steady::io::readMesh(path("split.off")); }, ErrorCode::InvalidFile,
              {"split.off", "line 7: expected face 0 as 'n i1 ... in' (n corner indices) on one line, got '3 0 2'"});
  writeText("hex.off", "OFF\n4 1 0\n0 0 0\n0x1p0 0 0\n0 1 0\n0 0 1\n3 0 2 1\n");
  expectError([&] { steady::io::readMesh(path("hex.off")); }, ErrorCode::InvalidFile,
              {"hex.off", "line 4: expected vertex 1 as three finite numbers"});
  writeText("big.off", "OFF\n4 1 0\n0 0 0\n1e400 0 0\n0 1 0\n0 0 1\n3 0 2 1\n");
  expectError([&] { steady::io::readMesh(path("big.off")); }, ErrorCode::InvalidFile,
              {"big.off", "line 4: expected vertex 1 as three finite numbers"});
  writeText("four.off", "4OFF\n4 1 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\n3 0 2 1\n");
  expectError([&] { steady::io::readMesh(path("four.off")); }, ErrorCode::InvalidFile,
              {"four.off", "line 1: the header '4OFF' announces 4D or n-dimensional vertices"});
}

// PLY is read by steady as its header declares, in ASCII one element per line. OpenMesh 9 read
// ASCII data as tokens: a line with one value too many shifted every later one until a
// coordinate was taken for a list of millions of indices (tests/fuzz/corpus/mesh/
// ply_ascii_line_shift).
TEST_F(MeshIo, ReadPlyAsItsHeaderDeclares) {
  const std::vector<Eigen::Vector3d> corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<std::array<int, 3>> faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const std::string vertex = "element vertex 4\nproperty double x\nproperty double y\nproperty double z\n";
  const std::string face = "element face 4\nproperty list uchar int vertex_indices\n";
  const std::string points = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::string tris = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const auto expectTetrahedron = [&](const std::string& name, const std::string& text) {
    SCOPED_TRACE(name);
    writeText(name, text);
    const TriangleMesh m = steady::io::readMesh(path(name));
    EXPECT_EQ(m.vertices, corners);
    EXPECT_EQ(m.faces, faces);
  };
  // faces before vertices, other elements and properties, integer coordinates, CRLF lines
  expectTetrahedron("order.ply", "ply\r\nformat ascii 1.0\r\nelement face 4\r\nproperty list uint8 uint32 vertex_index\r\n"
                                 "property uchar red\r\nelement vertex 4\r\nproperty int x\r\nproperty short y\r\n"
                                 "property float z\r\nproperty list uchar float uv\r\nelement edge 1\r\nproperty int a\r\n"
                                 "end_header\r\n3 0 2 1 255\r\n3 0 1 3 0\r\n3 0 3 2 7\r\n3 1 2 3 9\r\n0 0 0 0\r\n1 0 0 2 0.5 0.5\r\n"
                                 "0 1 0 0\r\n0 0 1 1 3\r\n5\r\n");
  {  // binary, little endian, with a list of another element between
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                      "property float z\nelement tag 2\nproperty list ushort char name\n" + face + "end_header\n";
    auto put = [&](const auto& x) { ply.append(reinterpret_cast<const char*>(&x), sizeof x); };  // the test host is little endian
    for (const Eigen::Vector3d& c : corners)
      for (int k = 0; k < 3; ++k) put(static_cast<float>(c[k]));
    put(std::uint16_t{3}), ply += "abc", put(std::uint16_t{0});
    for (const auto& f : faces) {
      put(std::uint8_t{3});
      for (const int v : f) put(std::int32_t{v});
    }
    expectTetrahedron("little.ply", ply);
    // a list count of 2^31 - 1 items: refused before anything is allocated
    std::string huge = ply.substr(0, ply.size() - 4 * 13);
    huge += '\xff';
    writeText("huge.ply", huge + std::string(12, '\xff'));
    expectError([&] { steady::io::readMesh(path("huge.ply")); }, ErrorCode::InvalidFile,
                {"huge.ply", "element 'face' 0: list 'vertex_indices' announces 255 items, but 3 values follow"});
  }

  const std::string head = "ply\nformat ascii 1.0\n" + vertex + face + "end_header\n";
  writeText("extra.ply", head + "0 0 0\n1 0 0 7\n0 1 0\n0 0 1\n" + tris);
  expectError([&] { steady::io::readMesh(path("extra.ply")); }, ErrorCode::InvalidFile,
              {"extra.ply", "line 11: element 'vertex' 1 has 1 values more than its properties declare", "own line"});
  writeText("few.ply", head + points + "3 0 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expectError([&] { steady::io::readMesh(path("few.ply")); }, ErrorCode::InvalidFile,
              {"few.ply", "line 14: element 'face' 0: list 'vertex_indices' announces 3 items, but 2 values follow"});
  writeText("short.ply", head + points + "3 0 2 1\n");
  expectError([&] { steady::io::readMesh(path("short.ply")); }, ErrorCode::InvalidFile,
              {"short.ply", "the file ends after 1 of the 4 elements 'face' its header announces"});
  writeText("count.ply", "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty double x\nproperty double y\n"
                         "property double z\nend_header\n0 0 0\n");
  expectError([&] { steady::io::readMesh(path("count.ply")); }, ErrorCode::InvalidFile,
              {"count.ply", "announces 99999999999 elements 'vertex', more than the file's 6 bytes of data can hold"});
  writeText("index.ply", head + points + "3 0 2 1\n3 0 1 3\n3 0 3 2.0\n3 1 2 3\n");
  expectError([&] { steady::io::readMesh(path("index.ply")); }, ErrorCode::InvalidFile,
              {"index.ply", "line 16: element 'face' 2: '2.0' is not an integer"});
  writeText("negative.ply", head + points + "3 0 2 1\n3 0 -1 3\n3 0 3 2\n3 1 2 3\n");
  expectError([&] { steady::io::readMesh(path("negative.ply")); }, ErrorCode::InvalidFile,
              {"negative.ply", "face 1 refers to vertex -1"});
  writeText("nan.ply", head + "0 0 0\n1 nan 0\n0 1 0\n0 0 1\n" + tris);
  expectError([&] { steady::io::readMesh(path("nan.ply")); }, ErrorCode::InvalidFile,
              {"nan.ply", "line 11: element 'vertex' 1: the vertex has a NaN or infinite coordinate"});
  writeText("novertex.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n" + face +
                                "end_header\n0 0\n1 0\n0 1\n0 0\n" + tris);
  expectError([&] { steady::io::readMesh(path("novertex.ply")); }, ErrorCode::InvalidFile,
              {"novertex.ply", "no element 'vertex' with the properties x, y and z"});
  writeText("realindex.ply", "ply\nformat ascii 1.0\n" + vertex + "element face 4\nproperty list uchar float vertex_indices\n"
                                 "end_header\n" + points + tris);
  expectError([&] { steady::io::readMesh(path("realindex.ply")); }, ErrorCode::InvalidFile,
              {"realindex.ply", "has a real item type; indices are integers"});
  writeText("empty.ply", "ply\nformat ascii 1.0\nelement thing 3\n" + vertex + face + "end_header\n" + points + tris);
  expectError([&] { steady::io::readMesh(path("empty.ply")); }, ErrorCode::InvalidFile,
              {"empty.ply", "element 'thing' declares no property"});
  writeText("noformat.ply", "ply\n" + vertex + face + "end_header\n" + points + tris);
  expectError([&] { steady::io::readMesh(path("noformat.ply")); }, ErrorCode::InvalidFile,
              {"noformat.ply", "its header has no 'format' line"});
}

TEST_F(MeshIo, ReadingPrintsNothing) {
  writeText("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n");
  ::testing::internal::CaptureStderr();
  ::testing::internal::CaptureStdout();
  EXPECT_THROW(steady::io::readMesh(path("bad.off")), Error);
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

// --- atomic writes ---

TEST_F(MeshIo, WriteIntoMissingDirectoryFailsAndLeavesNothing) {
  const std::string target = path("no/such/dir/out.ply");
  expectError([&] { steady::io::writeMesh(target, awkwardBox()); }, ErrorCode::Io, {"out.ply", "No such file or directory"});
  EXPECT_FALSE(fs::exists(target));
  EXPECT_TRUE(entries().empty());
}

TEST_F(MeshIo, WriteOntoDirectoryFailsAndRemovesTheTemporary) {
  fs::create_directory(path("out.off"));
  expectError([&] { steady::io::writeMesh(path("out.off"), awkwardBox()); }, ErrorCode::Io, {"out.off"});
  EXPECT_EQ(entries(), std::vector<std::string>{"out.off"});
  EXPECT_TRUE(fs::is_directory(path("out.off")));
}

TEST_F(MeshIo, FailureInTheMiddleLeavesTheOldFile) {
  // A file size limit makes write() fail part-way (EFBIG): the old file must survive intact and
  // no temporary may remain.
  writeText("out.obj", "old content\n");
  TriangleMesh big;
  for (int i = 0; i < 2000; ++i) steady::io::append(big, awkwardBox());
  struct rlimit saved {};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  struct rlimit small = saved;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  bool threw = false;
  try {
    steady::io::writeMesh(path("out.obj"), big);
  } catch (const Error& e) {
    threw = true;
    EXPECT_EQ(e.code(), ErrorCode::Io);
    EXPECT_NE(std::string(e.what()).find("out.obj"), std::string::npos) << e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_TRUE(threw);
  EXPECT_EQ(readText(path("out.obj")), "old content\n");
  EXPECT_EQ(entries(), std::vector<std::string>{"out.obj"});
}

TEST_F(MeshIo, WriteReplacesAnExistingFileCompletely) {
  writeText("out.off", std::string(100000, 'x'));
  steady::io::writeMesh(path("out.off"), awkwardBox());
  expectSameMesh(steady::io::readMesh(path("out.off")), awkwardBox(), true);
  EXPECT_EQ(entries(), std::vector<std::string>{"out.off"});
}

TEST_F(MeshIo, WriteInTheCurrentDirectory) {
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_);
  steady::io::writeMesh("here.stl", awkwardBox(), MeshWriteOptions{true});
  fs::current_path(cwd);
  EXPECT_EQ(steady::io::readMesh(path("here.stl")).faces.size(), 12u);
}

TEST_F(MeshIo, InvalidWritesAreRefusedBeforeTouchingTheDisk) {
  writeText("keep.ply", "old\n");
  TriangleMesh bad_index = awkwardBox();
  bad_index.faces.push_back({0, 1, 8});
  expectError([&] { steady::io::writeMesh(path("keep.ply"), bad_index); }, ErrorCode::InvalidArgument, {"face 12 refers to vertex 8"});
  TriangleMesh nan = awkwardBox();
  nan.vertices[3].y() = std::nan("");
  expectError([&] { steady::io::writeMesh(path("keep.ply"), nan); }, ErrorCode::NonFinite, {"vertex 3"});
  TriangleMesh huge = awkwardBox();
  huge.vertices[2].x() = 1e300;
  expectError([&] { steady::io::writeMesh(path("x.stl"), huge, MeshWriteOptions{true}); }, ErrorCode::NonFinite, {"float range"});
  expectError([&] { steady::io::writeMesh(path("x.obj"), awkwardBox(), MeshWriteOptions{true}); }, ErrorCode::InvalidArgument,
              {".ply and .stl"});
  expectError([&] { steady::io::writeMesh(path("x.vtk"), awkwardBox()); }, ErrorCode::InvalidArgument, {"'.vtk'"});
  EXPECT_EQ(readText(path("keep.ply")), "old\n");
  EXPECT_EQ(entries(), std::vector<std::string>{"keep.ply"});
}

TEST_F(MeshIo, EmptyMeshWritesValidFiles) {
  for (const char* name : {"e.off", "e.obj", "e.ply", "e.stl"}) {
    steady::io::writeMesh(path(name), TriangleMesh{});
    EXPECT_TRUE(fs::exists(path(name)));
  }
}

// --- helpers ---

TEST(MeshHelpers, TransformedMapsVerticesAndKeepsFaces) {
  const TriangleMesh box = awkwardBox();
  const steady::Affine3 pose = steady::Affine3::translation({1, 2, 3}) * steady::Affine3::rotation({0, 0, 1}, 0.5) *
                               steady::Affine3::scaling({2, 1, 0.5});
  const TriangleMesh moved = steady::io::transformed(box, pose);
  ASSERT_EQ(moved.vertices.size(), box.vertices.size());
  EXPECT_EQ(moved.faces, box.faces);
  for (std::size_t i = 0; i < box.vertices.size(); ++i)
    EXPECT_LT((moved.vertices[i] - (pose.linear() * box.vertices[i] + pose.translation())).norm(), 1e-9);
}

TEST(MeshHelpers, AppendShiftsIndicesWithoutWelding) {
  TriangleMesh into = awkwardBox();
  const TriangleMesh part = awkwardBox();
  steady::io::append(into, part);
  ASSERT_EQ(into.vertices.size(), 16u);
  ASSERT_EQ(into.faces.size(), 24u);
  EXPECT_EQ(into.vertices[8], part.vertices[0]);
  EXPECT_EQ(into.faces[12], (std::array<int, 3>{8, 9, 10}));
  TriangleMesh empty;
  steady::io::append(empty, part);
  EXPECT_EQ(empty.faces, part.faces);
}

// Building a scene from many instances appends part after part: the arrays must grow
// geometrically (a few dozen reallocations for 4,000 parts), not once per call, which copied the
// whole scene on every append (quadratic: assembling the collide benchmark's scene of 3,200
// spheres took 5.0M page faults and about 15 s of system time).
TEST(MeshHelpers, AppendingManyPartsGrowsTheArraysGeometrically) {
  const TriangleMesh part = awkwardBox();
  TriangleMesh scene;
  int vertex_moves = 0, face_moves = 0;
  const void* vertices_at = nullptr;
  const void* faces_at = nullptr;
  const int parts = 4000;
  for (int i = 0; i < parts; ++i) {
    steady::io::append(scene, part);
    if (scene.vertices.data() != vertices_at) ++vertex_moves, vertices_at = scene.vertices.data();
    if (scene.faces.data() != faces_at) ++face_moves, faces_at = scene.faces.data();
  }
  ASSERT_EQ(scene.faces.size(), static_cast<std::size_t>(parts) * part.faces.size());
  EXPECT_EQ(scene.faces.back()[0], part.faces.back()[0] + (parts - 1) * static_cast<int>(part.vertices.size()));
  EXPECT_LE(vertex_moves, 40);
  EXPECT_LE(face_moves, 40);
}

}  // namespace
