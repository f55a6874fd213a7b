// Triangle meshes: reading through OpenMesh's format readers, atomic writing by steady itself.

#include <steady/io/mesh.hpp>

#include <steady/core/error.hpp>

#include <Eigen/Geometry>  // cross

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <system_error>

namespace steady::io {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(ErrorCode code, const std::string& message) { throw Error(code, message); }

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

const char* formatName(MeshFormat f) {
  switch (f) {
    case MeshFormat::Off: return "OFF";
    case MeshFormat::Ply: return "PLY";
    case MeshFormat::Obj: return "OBJ";
    case MeshFormat::Stl: return "STL";
  }
  return "?";
}

// The extension of a path, lower case, without the dot ("" when there is none).
std::string extensionOf(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  return ext.size() > 1 ? lower(ext.substr(1)) : std::string();
}

bool formatOf(const std::string& path, MeshFormat& out) {
  const std::string ext = extensionOf(path);
  if (ext == "off") out = MeshFormat::Off;
  else if (ext == "ply") out = MeshFormat::Ply;
  else if (ext == "obj") out = MeshFormat::Obj;
  else if (ext == "stl") out = MeshFormat::Stl;
  else return false;
  return true;
}

std::string unknownExtension(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  return "'" + path + "': " + (ext.empty() ? std::string("no file extension") : "unknown extension '" + ext + "'") +
         "; the mesh formats are .off, .ply, .obj and .stl (the extension selects the format)";
}

// --- reading ---------------------------------------------------------------------------------

// Receives what an OpenMesh reader finds, without building OpenMesh's half-edge structure:
// every vertex and every polygon exactly as in the file. Faces with an index outside the
// vertex list are counted; everything but positions and faces is ignored.
class Collector : public OpenMesh::IO::BaseImporter {
 public:
  using VertexHandle = OpenMesh::VertexHandle;
  using FaceHandle = OpenMesh::FaceHandle;
  using HalfedgeHandle = OpenMesh::HalfedgeHandle;
  using EdgeHandle = OpenMesh::EdgeHandle;
  using Vec2f = OpenMesh::Vec2f;
  using Vec3f = OpenMesh::Vec3f;
  using Vec3d = OpenMesh::Vec3d;
  using Vec3uc = OpenMesh::Vec3uc;
  using Vec4uc = OpenMesh::Vec4uc;
  using Vec4f = OpenMesh::Vec4f;
  using StatusInfo = OpenMesh::Attributes::StatusInfo;

  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<int>> polygons;
  std::size_t bad_faces = 0;       // faces naming a vertex that does not exist
  std::size_t first_bad_face = 0;  // index (in the file's face order) of the first one
  int first_bad_index = 0;
  std::size_t short_faces = 0;     // faces with fewer than three corners (ignored)
  // At most this many vertices, and faces: a file of n bytes holds fewer than n / 2 of either
  // in any of the four formats (at least 3 bytes a vertex, 4 a face). OpenMesh's readers follow
  // the counts of a header, not the file's end: an OFF variant whose garbage header announced
  // billions of vertices was read as zeros until 3 GB (a mesh fuzz input).
  std::size_t max_elements = std::numeric_limits<std::size_t>::max();
  struct TooMany : std::runtime_error {
    using std::runtime_error::runtime_error;
  };

  VertexHandle add_vertex(const Vec3f& p) override { return push(p[0], p[1], p[2]); }
  VertexHandle add_vertex(const Vec3d& p) override { return push(p[0], p[1], p[2]); }
  VertexHandle add_vertex() override { return push(0, 0, 0); }
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(const VHandles& corners) override {
    if (faces_seen_ >= max_elements) throw TooMany("faces");
    const std::size_t face = faces_seen_++;
    if (corners.size() < 3) {
      ++short_faces;
      return FaceHandle();
    }
    std::vector<int> poly;
    poly.reserve(corners.size());
    for (const VertexHandle& v : corners) {
      if (v.idx() < 0 || static_cast<std::size_t>(v.idx()) >= points.size()) {
        if (bad_faces++ == 0) {
          first_bad_face = face;
          first_bad_index = v.idx();
        }
        return FaceHandle();
      }
      poly.push_back(v.idx());
    }
    polygons.push_back(std::move(poly));
    return FaceHandle(static_cast<int>(polygons.size() - 1));
  }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_point(VertexHandle v, const Vec3f& p) override {
    if (v.idx() >= 0 && static_cast<std::size_t>(v.idx()) < points.size()) points[static_cast<std::size_t>(v.idx())] = {p[0], p[1], p[2]};
  }
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const Vec3f&) override {}
  void set_normal(VertexHandle, const Vec3d&) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_status(VertexHandle, const StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  void reserve(unsigned int nv, unsigned int, unsigned int nf) override {
    // Sizes come from file headers: reserve a sane amount only.
    points.reserve(std::min<std::size_t>({nv, std::size_t{1} << 24, max_elements}));
    polygons.reserve(std::min<std::size_t>({nf, std::size_t{1} << 24, max_elements}));
  }
  size_t n_vertices() const override { return points.size(); }
  size_t n_faces() const override { return polygons.size(); }
  size_t n_edges() const override { return 0; }
  std::size_t faces_seen() const { return faces_seen_; }

 private:
  VertexHandle push(double x, double y, double z) {
    if (points.size() >= max_elements) throw TooMany("vertices");
    points.emplace_back(x, y, z);
    return VertexHandle(static_cast<int>(points.size() - 1));
  }
  std::size_t faces_seen_ = 0;
};

// OpenMesh reports problems on its global streams omerr/omlog/omout (standard error and
// output by default). While a file is read they go to a string instead, which becomes part of
// the error message; the mutex keeps two readMesh calls from interleaving.
std::mutex& openMeshMutex() {
  static std::mutex m;
  return m;
}

// Where one OpenMesh stream writes once it has been redirected: to the capture of the read in
// progress, if any, else to the standard streams it wrote to before.
class OpenMeshSink : public std::streambuf {
 public:
  std::ostringstream* capture = nullptr;  // (set and reset under openMeshMutex)
  std::vector<std::ostream*> before;

 protected:
  int overflow(int c) override {
    if (c != traits_type::eof()) {
      const char ch = traits_type::to_char_type(c);
      xsputn(&ch, 1);
    }
    return traits_type::not_eof(c);
  }
  std::streamsize xsputn(const char* text, std::streamsize n) override {
    if (capture) {
      // (a reader that complains once per element of a huge announced count would fill the
      // memory: a PLY fuzz input reached 2 GB; the start of what it said is enough)
      const std::streamsize room = kMaxCapture - static_cast<std::streamsize>(capture->tellp());
      if (room > 0) capture->write(text, std::min(n, room));
    } else {
      for (std::ostream* s : before) s->write(text, n);
    }
    return n;
  }

 private:
  static constexpr std::streamsize kMaxCapture = 4096;
};


// While an instance lives, what OpenMesh says goes to a string. OpenMesh's streams are
// redirected once per process, to an OpenMeshSink each, which stays connected: connecting and
// disconnecting for every read leaked 16 bytes a target each time (mostream::disconnect does not
// delete the target that connect allocated: 144 bytes a read, found by
// tests/fuzz/fuzz_mesh.cpp). Call with openMeshMutex held.
class CaptureOpenMeshMessages {
 public:
  CaptureOpenMeshMessages() {
    for (Redirected& r : redirected()) {
      r.stream->flush();
      r.sink.capture = &text_;
    }
  }
  ~CaptureOpenMeshMessages() {
    for (Redirected& r : redirected()) {
      r.stream->flush();
      r.sink.capture = nullptr;
    }
  }
  CaptureOpenMeshMessages(const CaptureOpenMeshMessages&) = delete;
  CaptureOpenMeshMessages& operator=(const CaptureOpenMeshMessages&) = delete;

  // What OpenMesh said, on one line.
  std::string text() {
    for (Redirected& r : redirected()) r.stream->flush();
    std::string s = text_.str();
    std::replace(s.begin(), s.end(), '\n', ' ');
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
  }

 private:
  struct Redirected {
    OpenMesh::mostream* stream = nullptr;
    OpenMeshSink sink;
    std::ostream out{&sink};
  };
  // The three streams, redirected on first use (the standard streams each wrote to are
  // disconnected once; those targets are OpenMesh's to keep).
  static std::array<Redirected, 3>& redirected() {
    static std::array<Redirected, 3> r;
    static const bool connected = [] {
      OpenMesh::mostream* streams[3] = {&omerr(), &omlog(), &omout()};
      for (int k = 0; k < 3; ++k) {
        Redirected& x = r[static_cast<std::size_t>(k)];
        x.stream = streams[k];
        x.stream->flush();
        if (x.stream->disconnect(std::cerr)) x.sink.before.push_back(&std::cerr);
        if (x.stream->disconnect(std::cout)) x.sink.before.push_back(&std::cout);
        if (x.stream->disconnect(std::clog)) x.sink.before.push_back(&std::clog);
        x.stream->connect(x.out);
      }
      return true;
    }();
    (void)connected;
    return r;
  }
  std::ostringstream text_;
};

const char* article(MeshFormat f) { return f == MeshFormat::Ply ? "a" : "an"; }

// Whether token t is one decimal number (an optional sign, digits with an optional point, an
// optional exponent; also inf and nan), read into x as the double nearest to it, as writeMesh's
// shortest form requires. std::from_chars, unlike strtod, does not depend on the C locale (a
// host program with a German LC_NUMERIC would have made "0.5" unreadable) and takes no
// hexadecimal.
bool wholeNumber(const std::string& t, double& x) {
  const char* first = t.data();
  const char* last = t.data() + t.size();
  if (first != last && *first == '+') {  // (from_chars takes '-' only)
    ++first;
    if (first == last || *first == '-' || *first == '+') return false;
  }
  const auto r = std::from_chars(first, last, x);
  return r.ec == std::errc() && r.ptr == last;
}

// Whether token t is one decimal integer (an optional '-', digits), read into x.
bool wholeInteger(const std::string& t, long long& x) {
  const auto r = std::from_chars(t.data(), t.data() + t.size(), x);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

// A mesh file read by steady's own parsers (text OFF, PLY), as the file holds it.
struct ParsedMesh {
  bool read = false;  // false: left to OpenMesh (a binary OFF)
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<int>> polygons;  // the faces of three or more corners, in file order
};

// A text OFF file, read here rather than by OpenMesh. OpenMesh's text OFF reader reads a face as
// tokens, not as a line: a face line with a colour after its corners (which OFF allows) shifts
// every later face, silently (a tetrahedron came back with 760 triangles), or until a coordinate
// taken for a corner count allocates gigabytes (a mesh fuzz input). It also takes counts written
// on the header line for vertex coordinates, misreads comments, truncated files and hexadecimal
// numbers, and rounds coordinates to float. Here each vertex and each face is one line ('#'
// starts a comment), as the header and counts announce; coordinates are kept in double.

// A line of a file as an error message shows it: its first 60 bytes, '?' for those that are not
// printable.
std::string shownLine(const std::string& line) {
  std::string shown = line.substr(0, 60);
  for (char& c : shown)
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  return shown;
}

ParsedMesh readTextOff(const std::string& path) {
  ParsedMesh off;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t line_no = 0;
  const auto bad = [&](const std::string& what) {
    fail(ErrorCode::InvalidFile, "the mesh '" + path + "' is not a valid OFF file: line " + std::to_string(line_no) + ": " + what);
  };
  // The next line with content, split into tokens ('#' starts a comment); false at the end.
  std::vector<std::string> tokens;
  const auto next = [&]() {
    while (std::getline(in, line)) {
      ++line_no;
      const auto hash = line.find('#');
      if (hash != std::string::npos) line.erase(hash);
      std::istringstream words(line);
      tokens.clear();
      for (std::string w; words >> w;) tokens.push_back(w);
      if (!tokens.empty()) return true;
    }
    return false;
  };
  const auto real = [](const std::string& t, double& x) { return wholeNumber(t, x) && std::isfinite(x); };
  // Tokens [from, tokens.size()) are numbers (a colour, normal or texture coordinates after a
  // vertex's position or a face's corners), at most `most` of them.
  const auto extras = [&](std::size_t from, std::size_t most, const std::string& what) {
    double x = 0;
    if (tokens.size() - from > most)
      bad(what + " has " + std::to_string(tokens.size() - from) + " values after it, more than the " + std::to_string(most) +
          " a normal, colour or texture coordinates take; each " + what.substr(0, what.find(' ')) +
          " must be on its own line: '" + shownLine(line) + "'");
    for (std::size_t i = from; i < tokens.size(); ++i)
      if (!wholeNumber(tokens[i], x))
        bad(what + ": '" + shownLine(tokens[i]) + "' after it is not a number: '" + shownLine(line) + "'");
  };
  if (!next()) {
    line_no = 1;
    bad("the file is empty");
  }
  // The header: OFF or one of its variants [ST][C][N][4][n]OFF, which only add values after a
  // vertex's position (texture coordinates, colour, normal) or a face's corners (colour).
  std::string rest = tokens[0];
  for (const char* prefix : {"ST", "C", "N", "4", "n"})
    if (rest.rfind(prefix, 0) == 0) rest.erase(0, std::strlen(prefix));
  // (a fuzz input headed 'OFF3' made OpenMesh's reader take a line as a face of millions of
  // corners and allocate until 2 GB)
  if (rest != "OFF") bad("the header '" + shownLine(tokens[0]) + "' is neither OFF nor one of its variants [ST][C][N][4][n]OFF");
  if (tokens.size() > 1 && tokens[1] == "BINARY") return off;
  if (tokens[0].find_first_of("4n") != std::string::npos)
    bad("the header '" + tokens[0] + "' announces 4D or n-dimensional vertices; steady reads 3D meshes only");
  tokens.erase(tokens.begin());
  if (tokens.empty() && !next()) bad("the file ends before the counts 'vertices faces edges'");
  long long nv = -1, nf = -1, ne = 0;
  if (tokens.size() < 2 || tokens.size() > 3 || !wholeInteger(tokens[0], nv) || !wholeInteger(tokens[1], nf) || nv < 0 || nf < 0 ||
      (tokens.size() == 3 && !wholeInteger(tokens[2], ne)))
    bad("expected the counts 'vertices faces edges', got '" + shownLine(line) + "'");
  if (nv > std::numeric_limits<int>::max())
    bad("the file announces " + std::to_string(nv) + " vertices, more than steady's meshes index (2^31 - 1)");
  // (the counts come from the file: memory is reserved for what its size could hold at most)
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  const auto cap = [&](long long n) { return static_cast<std::size_t>(std::min<std::uintmax_t>(static_cast<std::uintmax_t>(n), ec ? 0 : bytes / 2 + 1)); };
  off.points.reserve(cap(nv));
  off.polygons.reserve(cap(nf));
  for (long long i = 0; i < nv; ++i) {
    if (!next()) bad("the file ends after " + std::to_string(i) + " of the " + std::to_string(nv) + " vertices it announces");
    Eigen::Vector3d x;
    if (tokens.size() < 3 || !real(tokens[0], x.x()) || !real(tokens[1], x.y()) || !real(tokens[2], x.z()))
      bad("expected vertex " + std::to_string(i) + " as three finite numbers 'x y z', got '" + shownLine(line) + "'");
    extras(3, 9, "vertex " + std::to_string(i));
    off.points.push_back(x);
  }
  for (long long i = 0; i < nf; ++i) {
    if (!next()) bad("the file ends after " + std::to_string(i) + " of the " + std::to_string(nf) + " faces it announces");
    long long k = -1;
    if (!wholeInteger(tokens[0], k) || k < 0 || static_cast<std::size_t>(k) + 1 > tokens.size())
      bad("expected face " + std::to_string(i) + " as 'n i1 ... in' (n corner indices) on one line, got '" + shownLine(line) + "'");
    std::vector<int> poly(static_cast<std::size_t>(k));
    for (long long c = 1; c <= k; ++c) {
      long long idx = -1;
      if (!wholeInteger(tokens[static_cast<std::size_t>(c)], idx) || idx < 0 || idx >= nv)
        bad("face " + std::to_string(i) + ": corner '" + shownLine(tokens[static_cast<std::size_t>(c)]) +
            "' is not a vertex index in 0.." + std::to_string(nv - 1));
      poly[static_cast<std::size_t>(c - 1)] = static_cast<int>(idx);
    }
    extras(static_cast<std::size_t>(k) + 1, 4, "face " + std::to_string(i));
    if (k >= 3) off.polygons.push_back(std::move(poly));
  }
  off.read = true;
  return off;
}

// The coordinates of an OBJ file's vertices ("v x y z ..." lines, in file order), in double:
// OpenMesh 9's OBJ reader rounds them to float. Empty when some "v" line does not start with
// three finite numbers: OpenMesh's reading then stands (it skips such lines).
std::vector<Eigen::Vector3d> objVertices(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<Eigen::Vector3d> points;
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string key;
    if (!(words >> key) || key != "v") continue;
    Eigen::Vector3d x;
    for (int k = 0; k < 3; ++k) {
      std::string t;
      if (!(words >> t) || !wholeNumber(t, x[k]) || !std::isfinite(x[k])) return {};
    }
    points.push_back(x);
  }
  return points;
}

// A PLY file, read here rather than by OpenMesh (ASCII and binary, either byte order). OpenMesh
// 9's PLY reader never returned on a header without "end_header" or with a version other than
// 1.0 (its complaints filled the memory), allocated without end for "element vertex4" (no count),
// crashed on a property line before any element line, and read ASCII data as tokens, so a line
// with one value too many shifted every later one until a coordinate was taken for a list of
// millions of indices (mesh fuzz inputs, tests/fuzz/corpus/mesh/ply_*); it also rounds
// coordinates to float. Here the header is checked line by line, and the data is read as the
// header declares it: in ASCII one element per line with exactly its values. The mesh is the
// "vertex" element's x, y and z (any numeric type) and the "face" element's list
// "vertex_indices" (or "vertex_index"); other elements and properties are read and ignored.
struct PlyProperty {
  std::string name;
  int type = 0;        // size in bytes (1, 2, 4, 8) of the value, or of a list's items
  bool real = false;   // float or double (else an integer type)
  bool is_signed = false;
  bool list = false;
  int count_type = 0;  // a list's count: size in bytes (an integer type)
  bool count_signed = false;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

ParsedMesh readPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  const std::string name = "the mesh '" + path + "' is not a valid PLY file: ";
  auto wordsOf = [](const std::string& l) {
    std::istringstream in_line(l);
    std::vector<std::string> w;
    for (std::string x; in_line >> x;) w.push_back(x);
    return w;
  };
  auto bad = [&](long long n, const std::string& why) {
    fail(ErrorCode::InvalidFile, name + "header line " + std::to_string(n) + " ('" + shownLine(line) + "') " + why);
  };
  // PLY's types: their size, whether real, whether signed; false for an unknown name.
  auto type = [](const std::string& t, int& size, bool& real, bool& is_signed) {
    struct T {
      const char* a;
      const char* b;
      int size;
      bool real, is_signed;
    };
    static const T kTypes[] = {{"char", "int8", 1, false, true},    {"uchar", "uint8", 1, false, false},
                               {"short", "int16", 2, false, true},  {"ushort", "uint16", 2, false, false},
                               {"int", "int32", 4, false, true},    {"uint", "uint32", 4, false, false},
                               {"float", "float32", 4, true, true}, {"double", "float64", 8, true, true}};
    for (const T& k : kTypes)
      if (t == k.a || t == k.b) {
        size = k.size, real = k.real, is_signed = k.is_signed;
        return true;
      }
    return false;
  };
  if (!std::getline(in, line) || wordsOf(line) != std::vector<std::string>{"ply"})
    fail(ErrorCode::InvalidFile, name + "it does not start with the line 'ply'");
  enum class Encoding { Ascii, Little, Big } encoding = Encoding::Ascii;
  bool format_seen = false, ended = false;
  std::vector<PlyElement> elements;
  long long line_no = 1;
  for (long long n = 2; std::getline(in, line); ++n) {
    line_no = n;
    const std::vector<std::string> w = wordsOf(line);
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    for (const char c : line)
      if (!std::isprint(static_cast<unsigned char>(c)) && c != '\t' && c != '\r') bad(n, "holds a byte that is not text");
    if (w[0] == "end_header") {
      ended = true;
      break;
    }
    if (w[0] == "format") {
      if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") ||
          w[2] != "1.0")
        bad(n, "is not 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      encoding = w[1] == "ascii" ? Encoding::Ascii : w[1] == "binary_little_endian" ? Encoding::Little : Encoding::Big;
      format_seen = true;
    } else if (w[0] == "element") {
      if (w.size() != 3 || w[2].find_first_not_of("0123456789") != std::string::npos || w[2].size() > 18)
        bad(n, "is not 'element <name> <count>'");
      elements.push_back({w[1], std::stoll(w[2]), {}});
    } else if (w[0] == "property") {
      if (elements.empty()) bad(n, "is a property before any element line");
      PlyProperty p;
      const bool scalar = w.size() == 3 && type(w[1], p.type, p.real, p.is_signed);
      bool real_count = false;
      const bool list = w.size() == 5 && w[1] == "list" && type(w[2], p.count_type, real_count, p.count_signed) &&
                        type(w[3], p.type, p.real, p.is_signed);
      if (!scalar && !list)
        bad(n, "is not 'property <type> <name>' or 'property list <type> <type> <name>' with PLY types "
               "(char, uchar, short, ushort, int, uint, float, double, or int8 ... float64)");
      if (list && real_count) bad(n, "gives a list a count of a real type; a count is an integer type");
      p.list = list;
      p.name = w.back();
      elements.back().properties.push_back(p);
    } else {
      bad(n, "is none of format, element, property, comment, obj_info and end_header");
    }
  }
  if (!ended) fail(ErrorCode::InvalidFile, name + "its header has no 'end_header' line");
  if (!format_seen) fail(ErrorCode::InvalidFile, name + "its header has no 'format' line");

  // Where the mesh is: the vertex element's x, y, z and the face element's index list.
  int vertex_element = -1, face_element = -1;
  std::array<int, 3> xyz{{-1, -1, -1}};
  int indices = -1;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const PlyElement& el = elements[e];
    if (el.properties.empty() && el.count > 0)
      fail(ErrorCode::InvalidFile, name + "element '" + shownLine(el.name) + "' declares no property");
    if (el.name == "vertex" && vertex_element < 0) {
      vertex_element = static_cast<int>(e);
      for (std::size_t p = 0; p < el.properties.size(); ++p)
        for (int k = 0; k < 3; ++k)
          if (el.properties[p].name == std::string(1, static_cast<char>('x' + k)) && !el.properties[p].list) xyz[static_cast<std::size_t>(k)] = static_cast<int>(p);
    }
    if (el.name == "face" && face_element < 0) {
      face_element = static_cast<int>(e);
      for (std::size_t p = 0; p < el.properties.size(); ++p)
        if (el.properties[p].list && (el.properties[p].name == "vertex_indices" || el.properties[p].name == "vertex_index")) {
          indices = static_cast<int>(p);
          if (el.properties[p].real)
            fail(ErrorCode::InvalidFile, name + "the faces' list '" + el.properties[p].name + "' has a real item type; indices are integers");
        }
      if (indices < 0 && el.count > 0)
        fail(ErrorCode::InvalidFile, name + "its face element has no list property 'vertex_indices' (or 'vertex_index')");
    }
  }
  if (vertex_element < 0 || xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)
    fail(ErrorCode::InvalidFile, name + "it has no element 'vertex' with the properties x, y and z");

  // The data: every element in order.
  std::error_code ec;
  const std::uintmax_t file_size = fs::file_size(path, ec);
  const auto data_start = static_cast<std::uintmax_t>(in.tellg());
  const std::uintmax_t data_bytes = ec || file_size < data_start ? 0 : file_size - data_start;
  for (const PlyElement& el : elements) {
    // (an element takes at least a byte per value in binary, two in ASCII: no more elements than
    // the file can hold, before anything is allocated)
    const std::uintmax_t least = static_cast<std::uintmax_t>(el.properties.size()) * (encoding == Encoding::Ascii ? 2 : 1);
    if (least > 0 && static_cast<std::uintmax_t>(el.count) > data_bytes / least + 1)
      fail(ErrorCode::InvalidFile, name + "its header announces " + std::to_string(el.count) + " elements '" + shownLine(el.name) +
                                       "', more than the file's " + std::to_string(data_bytes) + " bytes of data can hold");
  }
  ParsedMesh mesh;
  mesh.read = true;
  mesh.points.reserve(static_cast<std::size_t>(elements[static_cast<std::size_t>(vertex_element)].count));
  if (face_element >= 0) mesh.polygons.reserve(static_cast<std::size_t>(elements[static_cast<std::size_t>(face_element)].count));
  std::vector<std::vector<int>> corners;  // per face (the vertex count may come later)
  std::vector<char> binary;
  std::size_t at = 0;
  if (encoding != Encoding::Ascii) {
    binary.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // Binary: the next value of `size` bytes, as a double (real) or an integer.
  auto raw = [&](int size, std::uint64_t& bits) {
    if (binary.size() - at < static_cast<std::size_t>(size)) return false;
    bits = 0;
    for (int j = 0; j < size; ++j)
      bits = bits << 8 | static_cast<unsigned char>(binary[at + static_cast<std::size_t>(encoding == Encoding::Big ? j : size - 1 - j)]);
    at += static_cast<std::size_t>(size);
    return true;
  };
  auto integerOf = [](std::uint64_t bits, int size, bool is_signed) -> long long {
    if (!is_signed || size == 8) return static_cast<long long>(bits);
    const std::uint64_t sign = std::uint64_t{1} << (8 * size - 1);
    return static_cast<long long>((bits ^ sign)) - static_cast<long long>(sign);
  };
  auto realOf = [](std::uint64_t bits, int size) {
    if (size == 8) {
      double d;
      std::memcpy(&d, &bits, 8);
      return d;
    }
    const auto b32 = static_cast<std::uint32_t>(bits);
    float f;
    std::memcpy(&f, &b32, 4);
    return static_cast<double>(f);
  };
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const PlyElement& el = elements[e];
    const bool is_vertex = static_cast<int>(e) == vertex_element, is_face = static_cast<int>(e) == face_element;
    std::vector<std::string> tokens;
    for (long long i = 0; i < el.count; ++i) {
      const std::string which = "element '" + shownLine(el.name) + "' " + std::to_string(i);
      auto ends = [&]() {
        fail(ErrorCode::InvalidFile, name + "the file ends after " + std::to_string(i) + " of the " + std::to_string(el.count) +
                                         " elements '" + shownLine(el.name) + "' its header announces");
      };
      std::size_t token = 0;
      if (encoding == Encoding::Ascii) {
        do {
          if (!std::getline(in, line)) ends();
          ++line_no;
          tokens = wordsOf(line);
        } while (tokens.empty());
      }
      auto where = [&]() {
        return encoding == Encoding::Ascii ? "line " + std::to_string(line_no) + ": " + which : which;
      };
      // The next value of property p's type (size, real, sign): as a double and, for an integer
      // type, as an integer too.
      auto value = [&](int size, bool real, bool is_signed, double& x, long long& k) {
        if (encoding == Encoding::Ascii) {
          if (token >= tokens.size())
            fail(ErrorCode::InvalidFile, name + where() + " has fewer values than its properties declare: '" + shownLine(line) + "'");
          const std::string& t = tokens[token++];
          if (real ? !wholeNumber(t, x) : !wholeInteger(t, k))
            fail(ErrorCode::InvalidFile, name + where() + ": '" + shownLine(t) + "' is not " + (real ? "a number" : "an integer"));
          if (!real) x = static_cast<double>(k);
          return;
        }
        std::uint64_t bits = 0;
        if (!raw(size, bits)) ends();
        if (real) {
          x = realOf(bits, size);
        } else {
          k = integerOf(bits, size, is_signed);
          x = static_cast<double>(k);
        }
      };
      Eigen::Vector3d point = Eigen::Vector3d::Zero();
      for (std::size_t p = 0; p < el.properties.size(); ++p) {
        const PlyProperty& prop = el.properties[p];
        double x = 0;
        long long k = 0;
        if (!prop.list) {
          value(prop.type, prop.real, prop.is_signed, x, k);
          if (is_vertex)
            for (int c = 0; c < 3; ++c)
              if (xyz[static_cast<std::size_t>(c)] == static_cast<int>(p)) point[c] = x;
          continue;
        }
        long long count = 0;
        value(prop.count_type, false, prop.count_signed, x, count);
        // (each item takes at least a byte, or a token)
        const std::size_t left = encoding == Encoding::Ascii ? tokens.size() - token : (binary.size() - at) / static_cast<std::size_t>(prop.type);
        if (count < 0 || static_cast<unsigned long long>(count) > left)
          fail(ErrorCode::InvalidFile, name + where() + ": list '" + prop.name + "' announces " + std::to_string(count) +
                                           " items, but " + std::to_string(left) + " values follow");
        const bool keep = is_face && static_cast<int>(p) == indices;
        std::vector<int> items;
        if (keep) items.reserve(static_cast<std::size_t>(count));
        for (long long j = 0; j < count; ++j) {
          value(prop.type, prop.real, prop.is_signed, x, k);
          if (!keep) continue;
          if (k < 0 || k > std::numeric_limits<int>::max())
            fail(ErrorCode::InvalidFile, "the mesh '" + path + "' is corrupt: face " + std::to_string(corners.size()) +
                                             " refers to vertex " + std::to_string(k) + ", which is no vertex index");
          items.push_back(static_cast<int>(k));
        }
        if (keep) corners.push_back(std::move(items));
      }
      if (encoding == Encoding::Ascii && token != tokens.size())
        fail(ErrorCode::InvalidFile, name + where() + " has " + std::to_string(tokens.size() - token) +
                                         " values more than its properties declare (each element must be on its own line): '" +
                                         shownLine(line) + "'");
      if (is_vertex) {
        if (!point.allFinite())
          fail(ErrorCode::InvalidFile, name + where() + ": the vertex has a NaN or infinite coordinate");
        mesh.points.push_back(point);
      }
    }
  }
  const long long nv = static_cast<long long>(mesh.points.size());
  for (std::size_t f = 0; f < corners.size(); ++f) {
    for (const int v : corners[f])
      if (v >= nv)
        fail(ErrorCode::InvalidFile, "the mesh '" + path + "' is corrupt: face " + std::to_string(f) + " refers to vertex " +
                                         std::to_string(v) + " but there are " + std::to_string(nv) + " vertices");
    if (corners[f].size() >= 3) mesh.polygons.push_back(std::move(corners[f]));
  }
  return mesh;
}

// The face lines of an OBJ file ("f c1 c2 c3 ..."), checked before OpenMesh reads them: each
// corner must be "v", "v/t", "v//n" or "v/t/n" with v a nonzero integer, and a face at least
// three corners. OpenMesh 9, built with assertions (Debian's), aborts the whole process on a
// face line whose corners it cannot read ("f h 0 0", a mesh fuzz input).
void checkObjFaces(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  auto index = [](const std::string& t, bool may_be_empty) {
    if (t.empty()) return may_be_empty;
    long long x = 0;
    return wholeInteger(t, x) && x != 0;
  };
  for (long long n = 1; std::getline(in, line); ++n) {
    std::istringstream words(line);
    std::string key;
    if (!(words >> key) || key != "f") continue;
    int corners = 0;
    bool ok = true;
    for (std::string c; ok && words >> c; ++corners) {
      const auto s1 = c.find('/');
      const auto s2 = s1 == std::string::npos ? std::string::npos : c.find('/', s1 + 1);
      ok = index(c.substr(0, s1), false) &&
           (s1 == std::string::npos ||
            (index(c.substr(s1 + 1, s2 == std::string::npos ? std::string::npos : s2 - s1 - 1), true) &&
             (s2 == std::string::npos || index(c.substr(s2 + 1), false))));
    }
    if (!ok || corners < 3) {
      fail(ErrorCode::InvalidFile, "the mesh '" + path + "' is not a valid OBJ file: line " + std::to_string(n) + " ('" +
                                       shownLine(line) + "') is not a face 'f v1 v2 v3 ...' of at least three corners v, v/t, "
                                       "v//n or v/t/n (nonzero vertex numbers)");
    }
  }
}

// A binary STL (not starting with "solid") must be 84 + 50 n bytes long for its n triangles.
void checkBinaryStlSize(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[84];
  in.read(head, sizeof head);
  const std::streamsize got = in.gcount();
  std::size_t first = 0;
  while (first < static_cast<std::size_t>(got) && std::isspace(static_cast<unsigned char>(head[first]))) ++first;
  if (static_cast<std::size_t>(got) >= first + 5 && std::string(head + first, 5) == "solid") return;  // text STL
  if (got < 84)
    fail(ErrorCode::InvalidFile, "the mesh '" + path + "' is not a valid STL file: " + std::to_string(got) +
                                     " bytes, fewer than the 84 of a binary STL header and it does not start with 'solid'");
  std::uint32_t n = 0;
  for (int i = 3; i >= 0; --i) n = (n << 8) | static_cast<unsigned char>(head[80 + i]);
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  const std::uintmax_t want = 84 + 50 * static_cast<std::uintmax_t>(n);
  if (!ec && size != want)
    fail(ErrorCode::InvalidFile, "the mesh '" + path + "' is not a valid binary STL file: its header announces " +
                                     std::to_string(n) + " triangles (" + std::to_string(want) + " bytes) but it has " +
                                     std::to_string(size) + " bytes (truncated?)");
}

}  // namespace

// Reads a mesh file with OpenMesh: every vertex and polygon, or a typed error. `said` receives
// what OpenMesh printed, as " (OpenMesh: ...)", or nothing.
Collector readWithOpenMesh(const std::string& path, MeshFormat format, std::string& what_said) {
  const std::string name = "'" + path + "'";
  Collector collected;
  {
    std::error_code ec;
    const std::uintmax_t bytes = fs::file_size(path, ec);
    if (!ec) collected.max_elements = static_cast<std::size_t>(bytes / 2 + 16);
  }
  bool ok = false;
  std::string said;
  {
    const std::lock_guard<std::mutex> lock(openMeshMutex());
    CaptureOpenMeshMessages capture;
    OpenMesh::IO::Options options;
    try {
      ok = OpenMesh::IO::IOManager().read(path, collected, options);
    } catch (const Collector::TooMany& e) {
      fail(ErrorCode::InvalidFile, "the mesh " + name + " has more " + e.what() + " than its size can hold (" +
                                       std::to_string(collected.max_elements) +
                                       " at most): its header announces more than the file contains; check the "
                                       "file (truncated, or a corrupt header)");
    } catch (const std::exception& e) {
      ok = false;
      said = e.what();
    }
    const std::string more = capture.text();
    said += (said.empty() || more.empty() ? "" : " ") + more;
  }
  const std::string fmt = formatName(format);
  what_said = said.empty() ? std::string() : " (OpenMesh: " + said + ")";
  if (!ok)
    fail(ErrorCode::InvalidFile, "cannot parse the mesh " + name + " as " + fmt + what_said +
                                     "; check that the file is a valid " + fmt + " file and that its extension matches its content");
  if (collected.bad_faces > 0)
    fail(ErrorCode::InvalidFile, "the mesh " + name + " is corrupt: face " + std::to_string(collected.first_bad_face) +
                                     " refers to vertex " + std::to_string(collected.first_bad_index) + " but there are " +
                                     std::to_string(collected.points.size()) + " vertices (" +
                                     std::to_string(collected.bad_faces) + " faces do)");
  return collected;
}

MeshFormat meshFormatOf(const std::string& path) {
  MeshFormat f{};
  if (!formatOf(path, f)) fail(ErrorCode::InvalidArgument, unknownExtension(path));
  return f;
}

TriangleMesh readMesh(const std::string& path) {
  MeshFormat format{};
  if (!formatOf(path, format)) fail(ErrorCode::InvalidFile, "cannot read the mesh " + unknownExtension(path));
  const std::string name = "'" + path + "'";
  {
    std::error_code ec;
    if (fs::is_directory(path, ec)) fail(ErrorCode::Io, "cannot read the mesh " + name + ": it is a directory");
    errno = 0;
    std::ifstream probe(path, std::ios::binary);
    if (!probe) {
      const int err = errno;
      fail(ErrorCode::Io, "cannot read the mesh " + name + ": " + (err ? std::strerror(err) : "cannot open the file") +
                              "; check the path and its permissions");
    }
  }

  ParsedMesh own;  // (text OFF and PLY: steady's parsers)
  if (format == MeshFormat::Off) own = readTextOff(path);
  if (format == MeshFormat::Ply) own = readPly(path);
  if (format == MeshFormat::Stl) checkBinaryStlSize(path);
  if (format == MeshFormat::Obj) checkObjFaces(path);

  TriangleMesh mesh;
  std::vector<std::vector<int>> polygons;
  std::string what_said;  // what OpenMesh said while reading, for the messages below
  if (own.read) {
    mesh.vertices = std::move(own.points);
    polygons = std::move(own.polygons);
  } else {
    Collector collected = readWithOpenMesh(path, format, what_said);
    // (an OBJ file's own coordinates, in double, where there are as many as OpenMesh read, in
    // float)
    std::vector<Eigen::Vector3d> exact = format == MeshFormat::Obj ? objVertices(path) : std::vector<Eigen::Vector3d>();
    mesh.vertices = exact.size() == collected.points.size() ? std::move(exact) : std::move(collected.points);
    polygons = std::move(collected.polygons);
  }
  const std::string fmt = formatName(format);
  for (const std::vector<int>& poly : polygons)
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) mesh.faces.push_back({poly[0], poly[i], poly[i + 1]});
  if (mesh.faces.empty())
    fail(ErrorCode::InvalidFile, "the mesh " + name + " holds no triangle (" + std::to_string(mesh.vertices.size()) +
                                     " vertices, no face with three or more corners)" + what_said +
                                     "; check that it is " + article(format) + " " + fmt + " file of a surface");
  for (const Eigen::Vector3d& v : mesh.vertices)
    if (!v.allFinite())
      fail(ErrorCode::InvalidFile, "the mesh " + name + " has a vertex with a NaN or infinite coordinate");
  return mesh;
}

// --- writing ---------------------------------------------------------------------------------

namespace {

// A failed system call while writing: errno and what was being done.
struct WriteFailure {
  int err;
  std::string doing;
};

// Buffered writes to a file descriptor; every failure becomes a WriteFailure.
class Sink {
 public:
  explicit Sink(int fd) : fd_(fd) { buffer_.reserve(kChunk + 256); }
  void put(const char* data, std::size_t n) {
    buffer_.append(data, n);
    if (buffer_.size() >= kChunk) flush();
  }
  void put(const std::string& s) { put(s.data(), s.size()); }
  void put(char c) { put(&c, 1); }
  void number(double x) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, x + 0.0);  // shortest round-trip form; no "-0"
    put(buf, static_cast<std::size_t>(r.ptr - buf));
  }
  void integer(long long x) { put(std::to_string(x)); }
  template <class T>
  void little(T value) {  // little-endian bytes of an integer or IEEE float
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (!hostIsLittle()) std::reverse(bytes, bytes + sizeof(T));
    put(reinterpret_cast<const char*>(bytes), sizeof(T));
  }
  void flush() {
    std::size_t done = 0;
    while (done < buffer_.size()) {
      const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
      if (n < 0) {
        if (errno == EINTR) continue;
        throw WriteFailure{errno, "writing"};
      }
      done += static_cast<std::size_t>(n);
    }
    buffer_.clear();
  }

 private:
  static bool hostIsLittle() {
    const std::uint16_t one = 1;
    unsigned char first = 0;
    std::memcpy(&first, &one, 1);
    return first == 1;
  }
  static constexpr std::size_t kChunk = std::size_t{1} << 20;
  int fd_;
  std::string buffer_;
};

void point(Sink& out, const Eigen::Vector3d& p) {
  out.number(p.x());
  out.put(' ');
  out.number(p.y());
  out.put(' ');
  out.number(p.z());
}

void writeOff(Sink& out, const TriangleMesh& m) {
  out.put("OFF\n");
  out.put(std::to_string(m.vertices.size()) + " " + std::to_string(m.faces.size()) + " 0\n");
  for (const auto& v : m.vertices) {
    point(out, v);
    out.put('\n');
  }
  for (const auto& f : m.faces) out.put("3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n");
}

void writeObj(Sink& out, const TriangleMesh& m) {
  out.put("# written by steady: " + std::to_string(m.vertices.size()) + " vertices, " + std::to_string(m.faces.size()) +
          " triangles\n");
  for (const auto& v : m.vertices) {
    out.put("v ");
    point(out, v);
    out.put('\n');
  }
  for (const auto& f : m.faces)
    out.put("f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n");
}

void writePly(Sink& out, const TriangleMesh& m, bool binary) {
  out.put(std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") + " 1.0\n" +
          "comment written by steady\n" + "element vertex " + std::to_string(m.vertices.size()) + "\n" +
          "property double x\nproperty double y\nproperty double z\n" + "element face " +
          std::to_string(m.faces.size()) + "\n" + "property list uchar int vertex_indices\nend_header\n");
  if (binary) {
    for (const auto& v : m.vertices) {
      out.little(v.x() + 0.0);
      out.little(v.y() + 0.0);
      out.little(v.z() + 0.0);
    }
    for (const auto& f : m.faces) {
      out.little(static_cast<std::uint8_t>(3));
      for (int i : f) out.little(static_cast<std::int32_t>(i));
    }
    return;
  }
  for (const auto& v : m.vertices) {
    point(out, v);
    out.put('\n');
  }
  for (const auto& f : m.faces) out.put("3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n");
}

Eigen::Vector3d unitNormal(const TriangleMesh& m, const std::array<int, 3>& f) {
  const Eigen::Vector3d& a = m.vertices[static_cast<std::size_t>(f[0])];
  const Eigen::Vector3d& b = m.vertices[static_cast<std::size_t>(f[1])];
  const Eigen::Vector3d& c = m.vertices[static_cast<std::size_t>(f[2])];
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double len = n.norm();
  return len > 0 && std::isfinite(len) ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

void writeStl(Sink& out, const TriangleMesh& m, bool binary) {
  if (binary) {
    std::string header = "binary STL written by steady";  // must not start with "solid"
    header.resize(80, ' ');
    out.put(header);
    out.little(static_cast<std::uint32_t>(m.faces.size()));
    for (const auto& f : m.faces) {
      const Eigen::Vector3d n = unitNormal(m, f);
      for (int k = 0; k < 3; ++k) out.little(static_cast<float>(n(k)));
      for (int i : f)
        for (int k = 0; k < 3; ++k) out.little(static_cast<float>(m.vertices[static_cast<std::size_t>(i)](k)));
      out.little(static_cast<std::uint16_t>(0));
    }
    return;
  }
  out.put("solid steady\n");
  for (const auto& f : m.faces) {
    out.put("  facet normal ");
    point(out, unitNormal(m, f));
    out.put("\n    outer loop\n");
    for (int i : f) {
      out.put("      vertex ");
      point(out, m.vertices[static_cast<std::size_t>(i)]);
      out.put('\n');
    }
    out.put("    endloop\n  endfacet\n");
  }
  out.put("endsolid steady\n");
}

// Checks everything that can be checked before touching the disk.
void validateForWrite(const std::string& path, const TriangleMesh& m, MeshFormat format, bool binary) {
  if (binary && (format == MeshFormat::Off || format == MeshFormat::Obj))
    fail(ErrorCode::InvalidArgument, "'" + path + "': binary output is available for .ply and .stl only; " +
                                         formatName(format) + " is written as text");
  const std::size_t nv = m.vertices.size();
  for (std::size_t i = 0; i < m.faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int idx = m.faces[i][static_cast<std::size_t>(k)];
      if (idx < 0 || static_cast<std::size_t>(idx) >= nv)
        fail(ErrorCode::InvalidArgument, "cannot write '" + path + "': face " + std::to_string(i) + " refers to vertex " +
                                             std::to_string(idx) + " but the mesh has " + std::to_string(nv) +
                                             " vertices");
    }
  const double limit = binary && format == MeshFormat::Stl ? static_cast<double>(std::numeric_limits<float>::max())
                                                           : std::numeric_limits<double>::max();
  for (std::size_t i = 0; i < nv; ++i) {
    const Eigen::Vector3d& v = m.vertices[i];
    if (!v.allFinite())
      fail(ErrorCode::NonFinite, "cannot write '" + path + "': vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
    if (!(std::abs(v.x()) <= limit && std::abs(v.y()) <= limit && std::abs(v.z()) <= limit))
      fail(ErrorCode::NonFinite, "cannot write '" + path + "': vertex " + std::to_string(i) +
                                     " has a coordinate beyond the float range of binary STL (3.4e38); write .ply instead");
  }
}

std::atomic<unsigned> temp_counter{0};

}  // namespace

void writeMesh(const std::string& path, const TriangleMesh& mesh, const MeshWriteOptions& options) {
  const MeshFormat format = meshFormatOf(path);
  validateForWrite(path, mesh, format, options.binary);

  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string file = target.filename().string();
  const std::string name = "'" + path + "'";

  // A new file next to the target: O_EXCL never reuses an existing name; mode 0666 minus umask
  // gives the permissions of any newly created file.
  std::string temp;
  int fd = -1;
  for (int attempt = 0; fd < 0 && attempt < 100; ++attempt) {
    temp = (dir / ("." + file + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(temp_counter++))).string();
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) {
      const int err = errno;
      fail(ErrorCode::Io, "cannot write the mesh " + name + ": cannot create a file in '" + dir.string() + "': " +
                              std::strerror(err) + "; check that the directory exists and is writable");
    }
  }
  if (fd < 0) fail(ErrorCode::Io, "cannot write the mesh " + name + ": no free temporary file name in '" + dir.string() + "'");

  try {
    Sink out(fd);
    switch (format) {
      case MeshFormat::Off: writeOff(out, mesh); break;
      case MeshFormat::Ply: writePly(out, mesh, options.binary); break;
      case MeshFormat::Obj: writeObj(out, mesh); break;
      case MeshFormat::Stl: writeStl(out, mesh, options.binary); break;
    }
    out.flush();
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) throw WriteFailure{errno, "flushing"};
    const int closed = ::close(fd);
    fd = -1;
    if (closed != 0) throw WriteFailure{errno, "closing"};
    if (std::rename(temp.c_str(), path.c_str()) != 0) throw WriteFailure{errno, "renaming the finished file to"};
  } catch (const WriteFailure& e) {
    if (fd >= 0) ::close(fd);
    ::unlink(temp.c_str());
    std::string hint;
    if (e.err == ENOSPC || e.err == EDQUOT) hint = "; free some disk space";
    else if (e.err == EISDIR) hint = "; the output path is a directory";
    else if (e.err == EACCES || e.err == EPERM) hint = "; check the permissions";
    fail(ErrorCode::Io, "cannot write the mesh " + name + ": error while " + e.doing + " it: " + std::strerror(e.err) +
                            hint + " (nothing was written)");
  } catch (...) {
    if (fd >= 0) ::close(fd);
    ::unlink(temp.c_str());
    throw;
  }
}

// --- helpers -----------------------------------------------------------------------------------

TriangleMesh transformed(const TriangleMesh& mesh, const steady::Affine3& pose) {
  TriangleMesh out;
  out.vertices.reserve(mesh.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices) out.vertices.push_back(pose.applyPoint(v));
  out.faces = mesh.faces;
  return out;
}

void append(TriangleMesh& into, const TriangleMesh& part) {
  const std::size_t offset = into.vertices.size();
  if (part.vertices.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()) - offset)
    fail(ErrorCode::InvalidArgument, "append: the merged mesh would hold " + std::to_string(offset) + " + " +
                                         std::to_string(part.vertices.size()) +
                                         " vertices, more than an int face index can address");
  const int shift = static_cast<int>(offset);
  into.vertices.insert(into.vertices.end(), part.vertices.begin(), part.vertices.end());
  // (no reserve of the exact size: it would copy every face of `into` again on each call, so
  // that appending n parts cost O(n^2); push_back grows the capacity geometrically)
  for (const auto& f : part.faces) into.faces.push_back({f[0] + shift, f[1] + shift, f[2] + shift});
}

}  // namespace steady::io
