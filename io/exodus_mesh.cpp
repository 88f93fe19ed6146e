#include "io/exodus_mesh.h"

#include <fmt/format.h>
#include <netcdf.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "io/grid_faces.h"

namespace hexmesh {
namespace {

// The sides of an Exodus HEX8, as 0-based local nodes (side s + 1 is entry s).
constexpr std::array<std::array<int, 4>, 6> exodus_sides = {
    {{0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {0, 4, 7, 3}, {0, 3, 2, 1}, {4, 5, 6, 7}}};

constexpr int name_length = 33;  // Exodus's default name length, with the terminating zero

class NetcdfFile {
  public:
    explicit NetcdfFile(const std::string& path) : path_(path) {
        check(nc_create(path.c_str(), NC_CLOBBER | NC_64BIT_OFFSET, &id_), "create");
    }
    ~NetcdfFile() {
        if (id_ >= 0) nc_close(id_);
    }
    void check(int status, const char* what) const {
        if (status != NC_NOERR)
            throw std::runtime_error(
                fmt::format("{}: Exodus (netCDF) {}: {}", path_, what, nc_strerror(status)));
    }
    int dim(const std::string& name, size_t length) {
        int d = 0;
        check(nc_def_dim(id_, name.c_str(), length, &d), "dimension");
        return d;
    }
    int var(const std::string& name, nc_type type, std::initializer_list<int> dims) {
        int v = 0;
        const std::vector<int> d(dims);
        check(nc_def_var(id_, name.c_str(), type, int(d.size()), d.data(), &v), "variable");
        return v;
    }
    void text_attribute(int var, const char* name, const std::string& value) {
        check(nc_put_att_text(id_, var, name, value.size(), value.c_str()), "attribute");
    }
    void close() {
        const int id = id_;
        id_ = -1;
        check(nc_close(id), "close");
    }
    int id() const { return id_; }

  private:
    std::string path_;
    int id_ = -1;
};

// Names as a [count][name_length] block of zero-padded characters.
std::vector<char> name_block(const std::vector<std::string>& names) {
    std::vector<char> block(names.size() * name_length, '\0');
    for (size_t n = 0; n < names.size(); ++n)
        std::memcpy(&block[n * name_length], names[n].data(),
                    std::min<size_t>(names[n].size(), name_length - 1));
    return block;
}

}  // namespace

void write_exodus_mesh(const BlockGrid& grid, const std::string& path) {
    const GridFaces faces = make_grid_faces(grid);
    const int npatches = int(faces.patch_names.size());
    std::vector<std::array<Id, 8>> cells;
    cells.reserve(size_t(grid.num_cells()));
    for (const Block& b : grid.blocks)
        for_each_cell(b, [&](int, int, int, const std::array<Id, 8>& n) { cells.push_back(n); });
    if (grid.points.size() >= (size_t(1) << 31) || cells.size() >= (size_t(1) << 31))
        throw std::runtime_error(path + ": too large for Exodus's 32-bit ids");
    // Per patch: each face's element (1-based) and side.
    std::vector<std::vector<int>> element(npatches), side(npatches);
    for (int p = 0; p < npatches; ++p)
        for_each_patch_face(grid, faces, p, [&](Id owner, const std::array<Id, 4>& n) {
            std::array<Id, 4> want = n;
            std::sort(want.begin(), want.end());
            const std::array<Id, 8>& c = cells[size_t(owner)];
            for (int s = 0; s < 6; ++s) {
                std::array<Id, 4> got;
                for (int m = 0; m < 4; ++m) got[m] = c[exodus_sides[s][m]];
                std::sort(got.begin(), got.end());
                if (got == want) {
                    element[p].push_back(int(owner + 1));
                    side[p].push_back(s + 1);
                    return;
                }
            }
            throw std::logic_error("write_exodus_mesh: a patch face is no side of its cell");
        });

    NetcdfFile f(path);
    const int id = f.id();
    f.text_attribute(
        NC_GLOBAL, "title",
        fmt::format("hexmesh: {} hexahedra, {} boundary patches", cells.size(), npatches));
    const float version = 8.03f;
    const int word_size = 8, file_size = 1;
    f.check(nc_put_att_float(id, NC_GLOBAL, "api_version", NC_FLOAT, 1, &version), "attribute");
    f.check(nc_put_att_float(id, NC_GLOBAL, "version", NC_FLOAT, 1, &version), "attribute");
    f.check(nc_put_att_int(id, NC_GLOBAL, "floating_point_word_size", NC_INT, 1, &word_size),
            "attribute");
    f.check(nc_put_att_int(id, NC_GLOBAL, "file_size", NC_INT, 1, &file_size), "attribute");
    const int len_name = f.dim("len_name", name_length);
    f.dim("len_string", name_length);
    f.dim("len_line", 81);
    f.dim("four", 4);
    const int time_step = f.dim("time_step", NC_UNLIMITED);
    const int num_dim = f.dim("num_dim", 3);
    const int num_nodes = f.dim("num_nodes", grid.points.size());
    f.dim("num_elem", cells.size());
    const int num_el_blk = f.dim("num_el_blk", 1);
    const int in_block = f.dim("num_el_in_blk1", cells.size());
    const int per_element = f.dim("num_nod_per_el1", 8);
    int num_side_sets = -1;
    if (npatches > 0) num_side_sets = f.dim("num_side_sets", size_t(npatches));
    std::vector<int> side_dims(npatches);
    for (int p = 0; p < npatches; ++p)
        side_dims[p] = f.dim(fmt::format("num_side_ss{}", p + 1), element[p].size());

    f.var("time_whole", NC_DOUBLE, {time_step});
    const int coord_names = f.var("coor_names", NC_CHAR, {num_dim, len_name});
    const int coord[3] = {f.var("coordx", NC_DOUBLE, {num_nodes}),
                          f.var("coordy", NC_DOUBLE, {num_nodes}),
                          f.var("coordz", NC_DOUBLE, {num_nodes})};
    const int eb_status = f.var("eb_status", NC_INT, {num_el_blk});
    const int eb_prop = f.var("eb_prop1", NC_INT, {num_el_blk});
    f.text_attribute(eb_prop, "name", "ID");
    const int eb_names = f.var("eb_names", NC_CHAR, {num_el_blk, len_name});
    const int connect = f.var("connect1", NC_INT, {in_block, per_element});
    f.text_attribute(connect, "elem_type", "HEX8");
    int ss_status = -1, ss_prop = -1, ss_names = -1;
    std::vector<int> elem_ss(npatches), side_ss(npatches);
    if (npatches > 0) {
        ss_status = f.var("ss_status", NC_INT, {num_side_sets});
        ss_prop = f.var("ss_prop1", NC_INT, {num_side_sets});
        f.text_attribute(ss_prop, "name", "ID");
        ss_names = f.var("ss_names", NC_CHAR, {num_side_sets, len_name});
        for (int p = 0; p < npatches; ++p) {
            elem_ss[p] = f.var(fmt::format("elem_ss{}", p + 1), NC_INT, {side_dims[p]});
            side_ss[p] = f.var(fmt::format("side_ss{}", p + 1), NC_INT, {side_dims[p]});
        }
    }
    f.check(nc_enddef(id), "header");

    f.check(nc_put_var_text(id, coord_names, name_block({"x", "y", "z"}).data()), "coor_names");
    std::vector<double> xyz(grid.points.size());
    for (int a = 0; a < 3; ++a) {
        for (size_t v = 0; v < grid.points.size(); ++v) xyz[v] = grid.points[v][a];
        f.check(nc_put_var_double(id, coord[a], xyz.data()), "coordinates");
    }
    const int one = 1;
    f.check(nc_put_var_int(id, eb_status, &one), "eb_status");
    f.check(nc_put_var_int(id, eb_prop, &one), "eb_prop1");
    f.check(nc_put_var_text(id, eb_names, name_block({"fluid"}).data()), "eb_names");
    std::vector<int> table(cells.size() * 8);
    for (size_t c = 0; c < cells.size(); ++c)
        for (int m = 0; m < 8; ++m) table[c * 8 + m] = int(cells[c][m] + 1);
    f.check(nc_put_var_int(id, connect, table.data()), "connect1");
    if (npatches > 0) {
        std::vector<int> status(npatches, 1), ids(npatches);
        for (int p = 0; p < npatches; ++p) ids[p] = p + 1;
        f.check(nc_put_var_int(id, ss_status, status.data()), "ss_status");
        f.check(nc_put_var_int(id, ss_prop, ids.data()), "ss_prop1");
        f.check(nc_put_var_text(id, ss_names, name_block(faces.patch_names).data()), "ss_names");
        for (int p = 0; p < npatches; ++p) {
            f.check(nc_put_var_int(id, elem_ss[p], element[p].data()), "elem_ss");
            f.check(nc_put_var_int(id, side_ss[p], side[p].data()), "side_ss");
        }
    }
    f.close();
}

}  // namespace hexmesh
