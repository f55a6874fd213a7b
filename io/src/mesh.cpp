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

// A text OFF file, read here rather than by OpenMesh. OpenMesh's text OFF reader reads a face as
// tokens, not as a line: a face line with a colour after its corners (which OFF allows) shifts
// every later face, silently (a tetrahedron came back with 760 triangles), or until a coordinate
// taken for a corner count allocates gigabytes (a mesh fuzz input). It also takes counts written
// on the header line for vertex coordinates, misreads comments, truncated files and hexadecimal
// numbers, and rounds coordinates to float. Here each vertex and each face is one line ('#'
// starts a comment), as the header and counts announce; coordinates are kept in double.
struct TextOff {
  bool read = false;  // false: a binary OFF, left to OpenMesh
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<int>> polygons;  // the faces of three or more corners, in file order
};

// A line of a file as an error message shows it: its first 60 bytes, '?' for those that are not
// printable.
std::string shownLine(const std::string& line) {
  std::string shown = line.substr(0, 60);
  for (char& c : shown)
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  return shown;
}

TextOff readTextOff(const std::string& path) {
  TextOff off;
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
  const auto integer = [&](const std::string& t, long long& out) {
    const auto r = std::from_chars(t.data(), t.data() + t.size(), out);
    return r.ec == std::errc() && r.ptr == t.data() + t.size();
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
  if (tokens.size() < 2 || tokens.size() > 3 || !integer(tokens[0], nv) || !integer(tokens[1], nf) || nv < 0 || nf < 0 ||
      (tokens.size() == 3 && !integer(tokens[2], ne)))
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
    if (!integer(tokens[0], k) || k < 0 || static_cast<std::size_t>(k) + 1 > tokens.size())
      bad("expected face " + std::to_string(i) + " as 'n i1 ... in' (n corner indices) on one line, got '" + shownLine(line) + "'");
    std::vector<int> poly(static_cast<std::size_t>(k));
    for (long long c = 1; c <= k; ++c) {
      long long idx = -1;
      if (!integer(tokens[static_cast<std::size_t>(c)], idx) || idx < 0 || idx >= nv)
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

// The coordinates of a PLY file's vertices, in double: OpenMesh 9's PLY reader rounds them to
// float, even where the file holds doubles (as writeMesh's binary PLY does). Read when the
// vertex element comes first and has only scalar properties, x, y and z among them (ASCII or
// binary, either byte order); empty otherwise, or for anything unexpected: OpenMesh's reading
// then stands.
std::vector<Eigen::Vector3d> plyVertices(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return {};
  enum class Encoding { Ascii, Little, Big } encoding = Encoding::Ascii;
  long long count = -1;
  bool vertex_first = false, in_vertex = false, header_done = false;
  std::vector<int> sizes;  // per vertex property: its size in bytes
  int coordinate[3] = {-1, -1, -1};
  std::vector<char> is_float;  // per vertex property: float or double (else an integer type)
  auto sizeOf = [](const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
  };
  int elements = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "format") {
      std::string f;
      words >> f;
      if (f == "ascii") encoding = Encoding::Ascii;
      else if (f == "binary_little_endian") encoding = Encoding::Little;
      else if (f == "binary_big_endian") encoding = Encoding::Big;
      else return {};
    } else if (key == "element") {
      std::string name;
      words >> name;
      in_vertex = ++elements == 1 && name == "vertex";
      if (in_vertex) {
        vertex_first = true;
        if (!(words >> count) || count < 0) return {};
      }
    } else if (key == "property" && in_vertex) {
      std::string type, name;
      words >> type >> name;
      const int size = sizeOf(type);
      if (size == 0) return {};  // a list, or an unknown type
      const int k = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : -1;
      if (k >= 0) coordinate[k] = static_cast<int>(sizes.size());
      sizes.push_back(size);
      is_float.push_back(type == "float" || type == "float32" || type == "double" || type == "float64");
    } else if (key == "end_header") {
      header_done = true;
      break;
    }
  }
  if (!header_done || !vertex_first || coordinate[0] < 0 || coordinate[1] < 0 || coordinate[2] < 0) return {};
  for (const int k : coordinate)
    if (!is_float[static_cast<std::size_t>(k)]) return {};
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<std::size_t>(std::min<long long>(count, 1 << 24)));
  std::vector<double> value(sizes.size());
  for (long long i = 0; i < count; ++i) {
    if (encoding == Encoding::Ascii) {
      if (!std::getline(in, line)) return {};
      std::istringstream words(line);
      for (double& v : value) {
        std::string t;
        if (!(words >> t) || !wholeNumber(t, v)) return {};
      }
    } else {
      for (std::size_t p = 0; p < sizes.size(); ++p) {
        unsigned char b[8];
        if (!in.read(reinterpret_cast<char*>(b), sizes[p])) return {};
        if (!is_float[p]) continue;
        // (the file's byte order to the machine's: assemble the bits most significant first)
        std::uint64_t bits = 0;
        for (int j = 0; j < sizes[p]; ++j) bits = bits << 8 | b[encoding == Encoding::Big ? j : sizes[p] - 1 - j];
        if (sizes[p] == 8) {
          std::memcpy(&value[p], &bits, 8);
        } else {
          const auto bits32 = static_cast<std::uint32_t>(bits);
          float f;
          std::memcpy(&f, &bits32, 4);
          value[p] = f;
        }
      }
    }
    const Eigen::Vector3d x(value[static_cast<std::size_t>(coordinate[0])], value[static_cast<std::size_t>(coordinate[1])],
                            value[static_cast<std::size_t>(coordinate[2])]);
    if (!x.allFinite()) return {};
    points.push_back(x);
  }
  return points;
}

// A PLY header must be well formed before OpenMesh 9's reader sees it: given a header without
// "end_header" it reads on forever (its complaints filled 2 GB), and given "element vertex4"
// (no count) it adds elements until the memory runs out, and given a property of type "int["
// it complains forever, as it does for a format version that is not "1.0", and a property
// line before any element line crashes it (five mesh fuzz inputs). So: the line "ply", then only these lines, in printable ASCII but for comments, up
// to "end_header": "format <ascii|binary_little_endian|binary_big_endian> 1.0",
// "element <name> <count>", "property <type> <name>", "property list <type> <type> <name>"
// (PLY's types), "comment ...", "obj_info ..." (and blank lines).
void checkPlyHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  auto wordsOf = [](const std::string& l) {
    std::istringstream in_line(l);
    std::vector<std::string> w;
    for (std::string x; in_line >> x;) w.push_back(x);
    return w;
  };
  auto bad = [&](long long n, const std::string& why) {
    fail(ErrorCode::InvalidFile, "the mesh '" + path + "' is not a valid PLY file: header line " + std::to_string(n) +
                                     " ('" + shownLine(line) + "') " + why);
  };
  auto type = [](const std::string& t) {
    static const char* const kTypes[] = {"char",  "uchar",  "short", "ushort",  "int",     "uint",
                                         "float", "double", "int8",  "uint8",   "int16",   "uint16",
                                         "int32", "uint32", "float32", "float64"};
    return std::find(std::begin(kTypes), std::end(kTypes), t) != std::end(kTypes);
  };
  if (!std::getline(in, line) || wordsOf(line) != std::vector<std::string>{"ply"})
    fail(ErrorCode::InvalidFile, "the mesh '" + path + "' is not a valid PLY file: it does not start with the line 'ply'");
  bool element_seen = false;
  for (long long n = 2; std::getline(in, line); ++n) {
    const std::vector<std::string> w = wordsOf(line);
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    for (const char c : line)
      if (!std::isprint(static_cast<unsigned char>(c)) && c != '\t' && c != '\r') bad(n, "holds a byte that is not text");
    if (w[0] == "end_header") return;
    if (w[0] == "format") {
      if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") ||
          w[2] != "1.0")
        bad(n, "is not 'format ascii|binary_little_endian|binary_big_endian 1.0'");
    } else if (w[0] == "element") {
      if (w.size() != 3 || w[2].find_first_not_of("0123456789") != std::string::npos || w[2].size() > 18)
        bad(n, "is not 'element <name> <count>'");
      element_seen = true;
    } else if (w[0] == "property") {
      // (OpenMesh adds a property to the last element without looking: a segmentation fault)
      if (!element_seen) bad(n, "is a property before any element line");
      if (!(w.size() == 3 && type(w[1])) && !(w.size() == 5 && w[1] == "list" && type(w[2]) && type(w[3])))
        bad(n, "is not 'property <type> <name>' or 'property list <type> <type> <name>' with PLY types "
               "(char, uchar, short, ushort, int, uint, float, double, or int8 ... float64)");
    } else {
      bad(n, "is none of format, element, property, comment, obj_info and end_header");
    }
  }
  fail(ErrorCode::InvalidFile, "the mesh '" + path + "' is not a valid PLY file: its header has no 'end_header' line");
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
    const auto r = std::from_chars(t.data(), t.data() + t.size(), x);
    return r.ec == std::errc() && r.ptr == t.data() + t.size() && x != 0;
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

  TextOff off;
  if (format == MeshFormat::Off) off = readTextOff(path);
  if (format == MeshFormat::Stl) checkBinaryStlSize(path);
  if (format == MeshFormat::Ply) checkPlyHeader(path);
  if (format == MeshFormat::Obj) checkObjFaces(path);

  TriangleMesh mesh;
  std::vector<std::vector<int>> polygons;
  std::string what_said;  // what OpenMesh said while reading, for the messages below
  if (off.read) {
    mesh.vertices = std::move(off.points);
    polygons = std::move(off.polygons);
  } else {
    Collector collected = readWithOpenMesh(path, format, what_said);
    // (an OBJ or PLY file's own coordinates, in double, where there are as many as OpenMesh
    // read, in float)
    std::vector<Eigen::Vector3d> exact = format == MeshFormat::Obj   ? objVertices(path)
                                         : format == MeshFormat::Ply ? plyVertices(path)
                                                                     : std::vector<Eigen::Vector3d>();
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
