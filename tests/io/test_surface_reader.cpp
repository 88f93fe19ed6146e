// Surface readers: STL (ASCII, binary), OBJ, OFF, PLY, and one clear message per bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/surface_reader.h"
#include "tests/io/scratch_files.h"
#include "tests/surface/sample_surfaces.h"

namespace hexmesh {
namespace {

class SurfaceReader : public test::ScratchFiles {
  protected:
    SurfaceReader() : ScratchFiles("hexmesh_reader_") {}

    // The InputError message of reading `file`, or "" if it reads fine.
    static std::string error_of(const std::string& file) {
        return test::input_error_of([](const std::string& f) { read_surface(f); }, file);
    }
};

TEST_F(SurfaceReader, BinaryStlStartingWithSolidMergesCorners) {
    const TriangleSurface sphere = test::uv_sphere(Vec3(1, 2, 3), 0.5, 24, 12);
    test::write_stl_binary(path("sphere.stl"), sphere);
    const TriangleSurface s = read_surface(path("sphere.stl"));
    EXPECT_EQ(s.triangles.size(), sphere.triangles.size());
    EXPECT_EQ(s.points.size(), sphere.points.size());  // 6 corners per point merged into 1
    for (size_t t = 0; t < s.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c)
            EXPECT_LT((s.points[s.triangles[t][c]] - sphere.points[sphere.triangles[t][c]]).norm(),
                      1e-6);
}

TEST_F(SurfaceReader, AsciiStlKeepsFullPrecision) {
    const TriangleSurface box = test::box_surface(Vec3(0.1, 0.2, 0.3), Vec3(1.7, 2.9, 3.1), 2);
    test::write_stl_ascii(path("box.STL"), box);
    const TriangleSurface s = read_surface(path("box.STL"));
    ASSERT_EQ(s.triangles.size(), box.triangles.size());
    EXPECT_EQ(s.points.size(), box.points.size());
    for (size_t t = 0; t < s.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(s.points[s.triangles[t][c]], box.points[box.triangles[t][c]]);
}

TEST_F(SurfaceReader, ObjPolygonsBecomeFansAndNegativeIndicesWork) {
    const std::string file = write("quad.obj",
                                   "# a unit square and a triangle\n"
                                   "mtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                   "vn 0 0 1\nvt 0 0\ng square\nf 1/1/1 2/1/1 3//1 4\n"
                                   "v 0 0 1\nf -5 -4 -1\n");
    const TriangleSurface s = read_surface(file);
    ASSERT_EQ(s.points.size(), 5u);
    ASSERT_EQ(s.triangles.size(), 3u);
    EXPECT_EQ(s.triangles[0], (std::array<int, 3>{0, 1, 2}));
    EXPECT_EQ(s.triangles[1], (std::array<int, 3>{0, 2, 3}));
    EXPECT_EQ(s.triangles[2], (std::array<int, 3>{0, 1, 4}));
}

TEST_F(SurfaceReader, OffWithCommentsAndColours) {
    const std::string file = write("tet.off",
                                   "OFF\n# a tetrahedron\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                   "3 0 2 1 255 0 0\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    const TriangleSurface s = read_surface(file);
    EXPECT_EQ(s.points.size(), 4u);
    ASSERT_EQ(s.triangles.size(), 4u);
    EXPECT_EQ(s.triangles[0], (std::array<int, 3>{0, 2, 1}));
}

const char* ply_header(const char* format) {
    static std::string h;
    h = std::string("ply\nformat ") + format +
        " 1.0\ncomment made by a test\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nelement face 2\n"
        "property list uchar int vertex_indices\nelement extra 1\nproperty double w\nend_header\n";
    return h.c_str();
}

TEST_F(SurfaceReader, PlyAscii) {
    const std::string file = write("square.ply", std::string(ply_header("ascii")) +
                                                     "0 0 0 9\n2 0 0 9\n2 2 0 9\n0 2 0 9\n"
                                                     "3 0 1 2\n3 0 2 3\n7.5\n");
    const TriangleSurface s = read_surface(file);
    ASSERT_EQ(s.points.size(), 4u);
    EXPECT_EQ(s.points[2], Vec3(2, 2, 0));
    ASSERT_EQ(s.triangles.size(), 2u);
    EXPECT_EQ(s.triangles[1], (std::array<int, 3>{0, 2, 3}));
}

TEST_F(SurfaceReader, PlyBinaryLittleEndian) {
    std::string data = ply_header("binary_little_endian");
    const float xyz[4][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
    for (const auto& p : xyz) {
        data.append(reinterpret_cast<const char*>(p), 12);
        data.push_back(char(7));
    }
    const int faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (const auto& f : faces) {
        data.push_back(char(3));
        data.append(reinterpret_cast<const char*>(f), 12);
    }
    const double w = 1;
    data.append(reinterpret_cast<const char*>(&w), 8);
    const TriangleSurface s = read_surface(write("square_bin.ply", data));
    ASSERT_EQ(s.triangles.size(), 2u);
    EXPECT_EQ(s.points[1], Vec3(2, 0, 0));
    EXPECT_EQ(s.triangles[1], (std::array<int, 3>{0, 2, 3}));
    // The same file cut in the middle of the faces.
    EXPECT_NE(
        error_of(write("cut.ply", data.substr(0, data.size() - 14))).find("face 2: truncated"),
        std::string::npos);
}

TEST_F(SurfaceReader, MissingAndEmptyFiles) {
    const std::string missing = error_of(path("nothere.stl"));
    EXPECT_NE(missing.find("nothere.stl: cannot open"), std::string::npos) << missing;
    const std::string empty = error_of(write("empty.obj", ""));
    EXPECT_NE(empty.find("empty.obj: empty file"), std::string::npos) << empty;
}

TEST_F(SurfaceReader, TruncatedBinaryStl) {
    test::write_stl_binary(path("full.stl"), test::box_surface(Vec3::Zero(), Vec3::Ones()));
    std::ifstream in(path("full.stl"), std::ios::binary);
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string e = error_of(write("cut.stl", data.substr(0, data.size() - 30)));
    EXPECT_NE(
        e.find("cut.stl: truncated binary STL: the header announces 12 triangles (684 bytes), "
               "the file has 654 bytes"),
        std::string::npos)
        << e;
}

TEST_F(SurfaceReader, NonFiniteVertexNamesTheLine) {
    const std::string e =
        error_of(write("nan.stl",
                       "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                       "vertex 1 0 0\nvertex nan 1 0\nendloop\nendfacet\nendsolid\n"));
    EXPECT_NE(e.find("nan.stl: line 6: vertex coordinates must be finite"), std::string::npos) << e;
    const std::string obj = error_of(write("inf.obj", "v 0 0 0\nv 1 0 inf\n"));
    EXPECT_NE(obj.find("inf.obj: line 2: vertex coordinates must be finite"), std::string::npos)
        << obj;
}

TEST_F(SurfaceReader, AFolderAndCoordinatesBeyondRangeAreNamedForWhatTheyAre) {
    std::filesystem::create_directories(path("folder.stl"));
    const std::string folder = error_of(path("folder.stl"));
    EXPECT_NE(folder.find("folder.stl: is a folder, not a surface file"), std::string::npos)
        << folder;
    const std::string huge =
        error_of(write("huge.off", "OFF\n3 1 0\n0 0 0\n1e308 0 0\n0 1 0\n3 0 1 2\n"));
    EXPECT_NE(
        huge.find(
            "huge.off: line 4: vertex coordinates up to 1e+150 are supported, got (1e+308, 0, 0)"),
        std::string::npos)
        << huge;
}

TEST_F(SurfaceReader, ZeroAreaTriangleIsRefusedUnlessAllowed) {
    const std::string file =
        write("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n");
    const std::string e = error_of(file);
    EXPECT_NE(e.find("flat.obj: line 6: zero-area triangle"), std::string::npos) << e;
    SurfaceReadOptions options;
    options.allow_degenerate = true;
    EXPECT_EQ(read_surface(file, options).triangles.size(), 2u);
}

TEST_F(SurfaceReader, FilesThatAreNotSurfaces) {
    const std::string json = error_of(write("case.stl", "{\"geometry\": {\"sphere\": {}}}\n"));
    EXPECT_NE(json.find("case.stl: not an STL file"), std::string::npos) << json;
    const std::string cloud = error_of(write("cloud.ply",
                                             "ply\nformat ascii 1.0\nelement vertex 2\nproperty "
                                             "float x\nproperty float y\nproperty float z\n"
                                             "end_header\n0 0 0\n1 1 1\n"));
    EXPECT_NE(cloud.find("cloud.ply: not a surface"), std::string::npos) << cloud;
    const std::string points = error_of(write("points.obj", "v 0 0 0\nv 1 0 0\n"));
    EXPECT_NE(points.find("points.obj: not a surface: the file holds no triangle"),
              std::string::npos)
        << points;
    const std::string kind = error_of(write("part.step", "ISO-10303-21;\n"));
    EXPECT_NE(kind.find("part.step: unknown surface format '.step'"), std::string::npos) << kind;
    const std::string garbage = error_of(write("junk.off", "hello world\n"));
    EXPECT_NE(garbage.find("junk.off: line 1: not an OFF file"), std::string::npos) << garbage;
}

TEST_F(SurfaceReader, IndexOutOfRange) {
    const std::string obj = error_of(write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"));
    EXPECT_NE(obj.find("bad.obj: line 4: vertex index 7 out of range"), std::string::npos) << obj;
    const std::string off =
        error_of(write("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"));
    EXPECT_NE(off.find("bad.off: line 6: vertex index '3' out of range"), std::string::npos) << off;
}

}  // namespace
}  // namespace hexmesh
