#pragma once
/// @file
/// Triangle meshes on disk: reading OFF, PLY, OBJ and STL files, writing them atomically, and
/// placing a mesh by a pose.
///
/// The file format is always chosen by the extension of the path (case-insensitive): `.off`,
/// `.ply`, `.obj`, `.stl`. Reading goes through steady's parsers (text OFF, PLY) or OpenMesh's
/// readers (OBJ, STL, binary OFF); writing is done by steady itself, so that the file holds
/// exactly the vertices and faces given, in their order, with every digit (OpenMesh's writers
/// would rebuild a half-edge mesh, which splits non-manifold faces, and print 6 significant
/// digits by default). Neither OpenMesh nor any other third-party type appears in this
/// interface.

#include <steady/core/affine.hpp>

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace steady::io {

/// An indexed triangle mesh: shared vertex positions and triangles as triples of vertex indices
/// (0-based). For a closed body the triangles are oriented counter-clockwise seen from outside
/// (right-hand rule: outward normals), which every format here keeps as it is.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;  ///< vertex positions
  std::vector<std::array<int, 3>> faces;  ///< triangles, indices into `vertices`
};

/// The mesh formats readMesh() and writeMesh() know.
enum class MeshFormat {
  Off,  ///< Object File Format (`.off`); written as text
  Ply,  ///< Stanford PLY (`.ply`); text or binary (little endian), coordinates as doubles
  Obj,  ///< Wavefront OBJ (`.obj`); positions and faces only, written as text
  Stl,  ///< STL (`.stl`); text or binary; binary STL stores coordinates as 32-bit floats
};

/// The format of a path, from its extension (case-insensitive).
/// @throws Error(InvalidArgument) for another or no extension; the message lists the known ones.
MeshFormat meshFormatOf(const std::string& path);

/// Reads a triangle mesh from an OFF, PLY, OBJ or STL file (the format comes from the
/// extension; OFF, PLY and STL may be text or binary). Text OFF (plain OFF and its variants
/// COFF, NOFF, STOFF, ...) and PLY (ASCII and binary, either byte order) are parsed by steady;
/// OBJ, STL and binary OFF by OpenMesh, whose findings steady collects without building
/// OpenMesh's half-edge structure. Either way the mesh is the file's content:
/// - vertices keep their order in the file; faces keep their order and corner order, and
///   non-manifold or degenerate faces are kept as they are;
/// - polygons with more than three corners become a fan of triangles around their first
///   corner (`(c0, c1, c2), (c0, c2, c3), ...`: exact for convex polygons); faces with fewer
///   than three corners are skipped;
/// - STL stores every triangle with its own corners: equal corners are merged into one vertex,
///   in order of first appearance;
/// - normals, colours, texture coordinates and other properties are ignored.
///
/// Precision: the coordinates of text OFF, OBJ and PLY files are read in double (in text, the
/// nearest double to each decimal, whatever the C locale), so a file written by writeMesh()
/// reads back exactly. OpenMesh 9's readers hold coordinates as 32-bit floats, and their
/// values (rounded to float, relative error at most 6e-8) stand for STL (text or binary) and
/// binary OFF.
///
/// Text OFF, as steady reads it: the header (OFF or a variant [ST][C][N]OFF; 4OFF and nOFF,
/// which are not 3D, are refused), the counts "vertices faces [edges]" (on the header's line or
/// the next), then one line per vertex ("x y z", finite, then at most 9 more numbers: normal,
/// colour, texture coordinates) and one line per face ("n i1 ... in" with indices in range,
/// then at most 4 more numbers: a colour); '#' starts a comment, blank lines are skipped, and
/// what follows the last face is ignored.
///
/// PLY, as steady reads it: a header of the lines "ply", "format ascii|binary_little_endian|
/// binary_big_endian 1.0", "element <name> <count>", "property <type> <name>", "property list
/// <count type> <item type> <name>" (PLY's types), "comment ...", "obj_info ..." up to
/// "end_header"; then every element as declared, in ASCII one per line with exactly its values.
/// The mesh is the element "vertex" (properties x, y, z of any numeric type) and the list
/// "vertex_indices" (or "vertex_index", of an integer type) of the element "face", which may
/// come in either order; other elements and properties are read and ignored. No element count
/// or list may announce more than the rest of the file can hold.
///
/// (OpenMesh 9 read text OFF faces and ASCII PLY data as tokens, not lines, so one value too
/// many on a line (a face colour, valid OFF) shifted every later value, silently or until it
/// allocated gigabytes; its PLY reader also never returned on some malformed headers. Each of
/// these answers an input found by fuzzing, tests/fuzz.)
///
/// Checks beyond OpenMesh's for the other formats: a binary OFF's header must be one of OFF's
/// variants; OBJ face lines must have at least three corners v, v/t, v//n or v/t/n (OpenMesh
/// aborts on others); a binary STL file must have the size its triangle count implies; a file
/// of n bytes yields at most n/2 + 16 vertices and faces (OpenMesh 9 follows header counts,
/// not the end of the file).
///
/// @throws Error(Io) when the file does not exist, is a directory or cannot be opened (the
///   message names the file and the system's reason);
///   Error(InvalidFile) for an extension other than the four above, for content that cannot
///   be parsed as the format of the extension (truncated, malformed, a face naming a vertex
///   that does not exist, a non-finite coordinate), or for a file without any triangle; the
///   message names the file and, where known, the line or face.
///
/// Thread safety: calls are serialised on a mutex, because OpenMesh's message streams
/// (omerr, omlog, omout) are redirected while a file is read, so that nothing is printed.
/// Other OpenMesh users in the same process should not read or write meanwhile.
TriangleMesh readMesh(const std::string& path);

/// Options of writeMesh().
struct MeshWriteOptions {
  /// Binary instead of text. Available for PLY (binary little endian, double coordinates) and
  /// STL (32-bit float coordinates, as the format prescribes); OFF and OBJ are text only.
  bool binary = false;
};

/// Writes a triangle mesh; the format comes from the extension of `path` (`.off`, `.ply`,
/// `.obj`, `.stl`).
///
/// Text formats hold every coordinate in the shortest decimal form that reads back to the same
/// double, binary PLY holds doubles: no digit is lost (binary STL holds floats, as the format
/// prescribes). OFF, PLY and OBJ
/// files hold exactly the given vertices and faces in their order; STL holds each triangle
/// with its three corners and its unit normal (0 for a degenerate triangle). An empty mesh
/// gives a valid empty file.
///
/// The write is atomic: the data goes to a new temporary file in the directory of `path`
/// (named `.<file name>.tmp-...`), which is flushed to disk and then renamed to `path`,
/// replacing any existing file. On any failure the temporary file is removed and `path` is left
/// as it was: a reader never sees a partial file. (If `path` is a symbolic link, the link
/// itself is replaced. A process killed while writing can leave the hidden temporary behind,
/// never a partial `path`.)
///
/// @throws Error(InvalidArgument) for an unknown extension, `binary` with OFF or OBJ, or a face
///   index outside the vertex list; Error(NonFinite) for a NaN or infinite coordinate (or, for
///   binary STL, one beyond the float range); all before anything is written.
///   Error(Io) when the file cannot be created, written, flushed or renamed (missing directory,
///   no permission, full disk, `path` is a directory, ...), with the file name and the
///   system's reason.
void writeMesh(const std::string& path, const TriangleMesh& mesh, const MeshWriteOptions& options = {});

/// The mesh with every vertex mapped by `pose` (`p -> L p + t`); faces are copied unchanged.
/// With `det L > 0` (every pose of a steady motion) the orientation of the faces is kept; a
/// mirroring pose (`det L < 0`) would turn the mesh inside out.
TriangleMesh transformed(const TriangleMesh& mesh, const steady::Affine3& pose);

/// Appends `part` to `into`: its vertices after those of `into`, its faces with their indices
/// shifted accordingly. Vertices are not welded (equal positions stay separate vertices).
/// @throws Error(InvalidArgument) when the merged mesh would hold more vertices than an `int`
///   face index can address (`into` is left unchanged then).
void append(TriangleMesh& into, const TriangleMesh& part);

}  // namespace steady::io
