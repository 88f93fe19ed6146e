// Point cloud (PLY, XYZ) and cross-section readers: round trips and one message per bad input.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "io/case_file.h"
#include "io/sample_readers.h"
#include "tests/io/scratch_files.h"

namespace hexmesh {
namespace {

namespace fs = std::filesystem;

// Numbers separated by spaces, at full precision.
std::string join(std::initializer_list<double> values) {
    std::ostringstream s;
    s << std::setprecision(17);
    for (double v : values) s << v << ' ';
    return s.str();
}

OrientedPoints sample_cloud() {
    OrientedPoints c;
    for (int i = 0; i < 20; ++i) {
        const double a = 0.3 * i;
        c.points.emplace_back(std::cos(a) + 0.125, std::sin(a) - 3.5e-7, 1e3 * i);
        c.normals.emplace_back(std::cos(a), std::sin(a), 0.25 * i);
    }
    return c;
}

class SampleReaders : public test::ScratchFiles {
  protected:
    SampleReaders() : ScratchFiles("hexmesh_samples_") {}

    static std::string cloud_error(const std::string& file) {
        return test::input_error_of(read_point_cloud, file);
    }
    static std::string stack_error(const std::string& file) {
        return test::input_error_of(read_sections, file);
    }
};

void expect_same(const OrientedPoints& a, const OrientedPoints& b, double tolerance) {
    ASSERT_EQ(a.points.size(), b.points.size());
    ASSERT_EQ(a.normals.size(), b.normals.size());
    for (size_t i = 0; i < a.points.size(); ++i) {
        EXPECT_LE((a.points[i] - b.points[i]).norm(), tolerance * (1 + a.points[i].norm()));
        EXPECT_LE((a.normals[i] - b.normals[i]).norm(), tolerance * (1 + a.normals[i].norm()));
    }
}

TEST_F(SampleReaders, XyzRoundTripWithComments) {
    const OrientedPoints cloud = sample_cloud();
    std::string text = "# x y z nx ny nz\n\n";
    for (size_t i = 0; i < cloud.points.size(); ++i)
        text += join({cloud.points[i].x(), cloud.points[i].y(), cloud.points[i].z(),
                      cloud.normals[i].x(), cloud.normals[i].y(), cloud.normals[i].z()}) +
                " # point " + std::to_string(i) + "\n";
    expect_same(read_point_cloud(write("a.XYZ", text)), cloud, 0);
}

TEST_F(SampleReaders, AsciiPlyRoundTripInAnyPropertyOrder) {
    const OrientedPoints cloud = sample_cloud();
    std::string text = "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex " +
                       std::to_string(cloud.points.size()) +
                       "\nproperty double nx\nproperty double ny\nproperty double nz\n"
                       "property uchar red\nproperty double x\nproperty double y\n"
                       "property double z\nelement face 0\n"
                       "property list uchar int vertex_indices\nend_header\n";
    for (size_t i = 0; i < cloud.points.size(); ++i)
        text += join({cloud.normals[i].x(), cloud.normals[i].y(), cloud.normals[i].z(), 255,
                      cloud.points[i].x(), cloud.points[i].y(), cloud.points[i].z()}) +
                "\n";
    expect_same(read_point_cloud(write("a.ply", text)), cloud, 0);
}

TEST_F(SampleReaders, BinaryPlyRoundTripWithFloatNormals) {
    const OrientedPoints cloud = sample_cloud();
    std::string data = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                       std::to_string(cloud.points.size()) +
                       "\nproperty double x\nproperty double y\nproperty double z\n"
                       "property float nx\nproperty float ny\nproperty float nz\n"
                       "property list uchar int extra\nend_header\n";
    for (size_t i = 0; i < cloud.points.size(); ++i) {
        for (int a = 0; a < 3; ++a)
            data.append(reinterpret_cast<const char*>(&cloud.points[i][a]), 8);
        for (int a = 0; a < 3; ++a) {
            const float n = float(cloud.normals[i][a]);
            data.append(reinterpret_cast<const char*>(&n), 4);
        }
        const unsigned char count = 2;
        const int extra[2] = {7, 8};
        data.append(reinterpret_cast<const char*>(&count), 1);
        data.append(reinterpret_cast<const char*>(extra), 8);
    }
    expect_same(read_point_cloud(write("b.ply", data)), cloud, 1e-6);
    EXPECT_NE(cloud_error(write("c.ply", data.substr(0, data.size() - 3)))
                  .find("c.ply: vertex 20: truncated binary PLY data"),
              std::string::npos);
}

TEST_F(SampleReaders, BadPointCloudsNameFileAndLine) {
    EXPECT_NE(cloud_error(path("missing.xyz")).find("missing.xyz: cannot open"), std::string::npos);
    EXPECT_NE(
        cloud_error(write("a.pts", "0 0 0 1 0 0\n")).find("unknown point cloud format '.pts'"),
        std::string::npos);
    EXPECT_NE(cloud_error(write("a.xyz", "")).find("a.xyz: empty file"), std::string::npos);
    EXPECT_NE(cloud_error(write("b.xyz", "# nothing\n\n")).find("b.xyz: no point"),
              std::string::npos);
    EXPECT_NE(
        cloud_error(write("c.xyz", "0 0 0 1 0 0\n1 2 3\n"))
            .find("c.xyz: line 2: expected 6 numbers 'x y z nx ny nz', got 3 (missing normals?)"),
        std::string::npos);
    EXPECT_NE(cloud_error(write("d.xyz", "0 0 0 1 0 0\n\n0 nan 0 1 0 0\n"))
                  .find("d.xyz: line 3: coordinates and normals must be finite numbers, got nan"),
              std::string::npos);
    EXPECT_NE(cloud_error(write("e.xyz", "0 0 0 0 0 0\n")).find("e.xyz: line 1: zero normal"),
              std::string::npos);
    EXPECT_NE(cloud_error(write("f.xyz", "0 0 zero 1 0 0\n"))
                  .find("f.xyz: line 1: expected a number, got 'zero'"),
              std::string::npos);
    EXPECT_NE(cloud_error(write("a.ply",
                                "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                "property float y\nproperty float z\nend_header\n0 0 0\n"))
                  .find("a.ply: PLY element 'vertex' lacks the property nx (a point cloud needs "
                        "normals nx ny nz)"),
              std::string::npos);
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
        "property float y\nproperty float z\nproperty float nx\n"
        "property float ny\nproperty float nz\nend_header\n";
    EXPECT_NE(cloud_error(write("b.ply", header + "0 0 0 1 0 0\n0 0 inf 1 0 0\n"))
                  .find("b.ply: line 12: coordinates and normals must be finite numbers, got inf"),
              std::string::npos);
    EXPECT_NE(cloud_error(write("c.ply", header + "0 0 0 1 0 0\n0 0\n"))
                  .find("c.ply: line 12: truncated ASCII PLY data"),
              std::string::npos);
    EXPECT_NE(cloud_error(write("d.ply", "plx\n")).find("d.ply: line 1: not a PLY file"),
              std::string::npos);
}

TEST_F(SampleReaders, SectionsRoundTripSortedWithIslands) {
    const std::string file =
        write("stack.txt",
              "# two squares, an island in the top one\n"
              "slice 2.5\n0 0\n4 0\n4 4\n0 4\n0 0\nloop\n1 1\n2 1\n2 2  # tri\n"
              "\n"
              "slice -1e-3\n0 0\n1 0\n1 1\n0 1\n");
    const SectionStack stack = read_sections(file);
    ASSERT_EQ(stack.sections.size(), 2u);
    EXPECT_EQ(stack.sections[0].z, -1e-3);
    EXPECT_EQ(stack.sections[1].z, 2.5);
    ASSERT_EQ(stack.sections[0].loops.size(), 1u);
    EXPECT_EQ(stack.sections[0].loops[0].size(), 4u);
    EXPECT_EQ(stack.sections[0].loops[0][2], Eigen::Vector2d(1, 1));
    ASSERT_EQ(stack.sections[1].loops.size(), 2u);
    EXPECT_EQ(stack.sections[1].loops[0].size(), 4u);  // the repeated closing point dropped
    EXPECT_EQ(stack.sections[1].loops[1].size(), 3u);
    EXPECT_EQ(stack.sections[1].loops[1][2], Eigen::Vector2d(2, 2));
}

TEST_F(SampleReaders, BadSectionsNameFileAndLine) {
    EXPECT_NE(stack_error(path("none.txt")).find("none.txt: cannot open"), std::string::npos);
    EXPECT_NE(stack_error(write("a.txt", "slice 0\n0 0\n1 0\n1 1\n"))
                  .find("a.txt: a stack of sections needs at least 2 'slice Z', got 1"),
              std::string::npos);
    EXPECT_NE(stack_error(write("b.txt", "slice 0\n0 0\n1 0\n1 1\nslice 1\n0 0\n1 0\n"))
                  .find("b.txt: line 5: a closed polyline needs at least 3 points, got 2"),
              std::string::npos);
    EXPECT_NE(stack_error(write("c.txt", "slice 0\n0 0\n1 0\n1 1\nloop\n0 0\n1 0\n0 0\nslice 1\n"))
                  .find("c.txt: line 5: a closed polyline needs at least 3 points, got 2"),
              std::string::npos);
    EXPECT_NE(stack_error(write("d.txt", "0 0\nslice 0\n"))
                  .find("d.txt: line 1: a point before the first"),
              std::string::npos);
    EXPECT_NE(stack_error(write("e.txt", "slice 0\n0 0\n1 nan\n"))
                  .find("e.txt: line 3: numbers must be finite, got nan"),
              std::string::npos);
    EXPECT_NE(stack_error(write("f.txt", "slice 0\n0 0 0\n"))
                  .find("f.txt: line 2: expected 'slice Z', 'loop' or a point 'x y', got 3 words"),
              std::string::npos);
    EXPECT_NE(stack_error(write("g.txt", "slice 1\n0 0\n1 0\n1 1\nslice 1.0\n0 0\n1 0\n1 1\n"))
                  .find("g.txt: line 5: a second slice at z = 1 (line 1)"),
              std::string::npos);
    EXPECT_NE(stack_error(write("h.txt", "slice top\n"))
                  .find("h.txt: line 1: expected a number, got 'top'"),
              std::string::npos);
}

TEST(CaseSampleFiles, PointsAndSectionsAreShapesWithPathsRelativeToTheCase) {
    const Case c = parse_case(
        R"({"geometry": {"union": [{"points": "cloud.ply", "scale": 2},
                                   {"sections": "../stacks/s.txt", "translate": [0, 0, 1]}]}})",
        "cases/x/case.json");
    ASSERT_EQ(c.geometry.children.size(), 2u);
    EXPECT_EQ(c.geometry.children[0].kind, BodyKind::points);
    EXPECT_EQ(c.geometry.children[0].file, "cases/x/cloud.ply");
    EXPECT_EQ(c.geometry.children[0].scale, 2);
    EXPECT_EQ(c.geometry.children[1].kind, BodyKind::sections);
    EXPECT_EQ(c.geometry.children[1].file, "cases/stacks/s.txt");
    const Case again = parse_case(case_to_json(c), "elsewhere/case.json");
    EXPECT_EQ(again.geometry.children[0].kind, BodyKind::points);
    EXPECT_EQ(again.geometry.children[0].file, fs::absolute("cases/x/cloud.ply").string());
    EXPECT_EQ(again.geometry.children[1].kind, BodyKind::sections);
    EXPECT_EQ(again.geometry.children[1].translate, Vec3(0, 0, 1));
}

TEST(CaseSampleFiles, BadValuesNameTheKey) {
    const auto error_of = [](const std::string& text) {
        try {
            parse_case(text, "case.json");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error_of(R"({"geometry": {"points": 1}})")
                  .find("geometry.points: expected a point cloud file name (.ply or .xyz)"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"sections": ""}})")
                  .find("geometry.sections: expected a cross-section file name"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"points": "a.xyz", "sections": "b.txt"}})")
                  .find("expected exactly one shape"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"points": "a.xyz", "voxel_size": 1}})")
                  .find("geometry.voxel_size: expected no voxel size"),
              std::string::npos);
}

}  // namespace
}  // namespace hexmesh
