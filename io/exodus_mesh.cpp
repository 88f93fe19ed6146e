#include "io/exodus_mesh.h"

#include <fmt/format.h>
#include <netcdf.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

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

// The grid's cells, block by block, as their 8 nodes (VTK order).
std::vector<std::array<Id, 8>> cells_of(const BlockGrid& grid, const std::string& path) {
    std::vector<std::array<Id, 8>> cells;
    cells.reserve(size_t(grid.num_cells()));
    for (const Block& b : grid.blocks)
        for_each_cell(b, [&](int, int, int, const std::array<Id, 8>& n) { cells.push_back(n); });
    if (grid.points.size() >= (size_t(1) << 31) || cells.size() >= (size_t(1) << 31))
        throw std::runtime_error(path + ": too large for Exodus's 32-bit ids");
    return cells;
}

// Per patch: each face's element (1-based) and side (1-based).
struct SideSets {
    std::vector<std::vector<int>> element, side;
};

SideSets side_sets(const BlockGrid& grid, const GridFaces& faces,
                   const std::vector<std::array<Id, 8>>& cells) {
    const int npatches = int(faces.patch_names.size());
    SideSets sets{std::vector<std::vector<int>>(npatches), std::vector<std::vector<int>>(npatches)};
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
                    sets.element[p].push_back(int(owner + 1));
                    sets.side[p].push_back(s + 1);
                    return;
                }
            }
            throw std::logic_error("write_exodus_mesh: a patch face is no side of its cell");
        });
    return sets;
}

// The file's title and Exodus's global attributes (version, word size, file size).
void put_global_attributes(NetcdfFile& f, size_t cells, int npatches) {
    const int id = f.id();
    f.text_attribute(NC_GLOBAL, "title",
                     fmt::format("hexmesh: {} hexahedra, {} boundary patches", cells, npatches));
    const float version = 8.03f;
    const int word_size = 8, file_size = 1;
    f.check(nc_put_att_float(id, NC_GLOBAL, "api_version", NC_FLOAT, 1, &version), "attribute");
    f.check(nc_put_att_float(id, NC_GLOBAL, "version", NC_FLOAT, 1, &version), "attribute");
    f.check(nc_put_att_int(id, NC_GLOBAL, "floating_point_word_size", NC_INT, 1, &word_size),
            "attribute");
    f.check(nc_put_att_int(id, NC_GLOBAL, "file_size", NC_INT, 1, &file_size), "attribute");
}

// The ids of the variables the header defines (the side sets' -1 or empty without patches).
struct Variables {
    int coord_names = -1;
    int coord[3] = {-1, -1, -1};
    int eb_status = -1, eb_prop = -1, eb_names = -1, connect = -1;
    int ss_status = -1, ss_prop = -1, ss_names = -1;
    std::vector<int> elem_ss, side_ss;
};

// Defines the dimensions and variables of one element block of `cells` hexahedra and a side
// set per patch, and ends the header.
Variables define_variables(NetcdfFile& f, size_t points, size_t cells, const SideSets& sets) {
    const int npatches = int(sets.element.size());
    const int len_name = f.dim("len_name", name_length);
    f.dim("len_string", name_length);
    f.dim("len_line", 81);
    f.dim("four", 4);
    const int time_step = f.dim("time_step", NC_UNLIMITED);
    const int num_dim = f.dim("num_dim", 3);
    const int num_nodes = f.dim("num_nodes", points);
    f.dim("num_elem", cells);
    const int num_el_blk = f.dim("num_el_blk", 1);
    const int in_block = f.dim("num_el_in_blk1", cells);
    const int per_element = f.dim("num_nod_per_el1", 8);
    int num_side_sets = -1;
    if (npatches > 0) num_side_sets = f.dim("num_side_sets", size_t(npatches));
    std::vector<int> side_dims(npatches);
    for (int p = 0; p < npatches; ++p)
        side_dims[p] = f.dim(fmt::format("num_side_ss{}", p + 1), sets.element[p].size());

    Variables v;
    f.var("time_whole", NC_DOUBLE, {time_step});
    v.coord_names = f.var("coor_names", NC_CHAR, {num_dim, len_name});
    v.coord[0] = f.var("coordx", NC_DOUBLE, {num_nodes});
    v.coord[1] = f.var("coordy", NC_DOUBLE, {num_nodes});
    v.coord[2] = f.var("coordz", NC_DOUBLE, {num_nodes});
    v.eb_status = f.var("eb_status", NC_INT, {num_el_blk});
    v.eb_prop = f.var("eb_prop1", NC_INT, {num_el_blk});
    f.text_attribute(v.eb_prop, "name", "ID");
    v.eb_names = f.var("eb_names", NC_CHAR, {num_el_blk, len_name});
    v.connect = f.var("connect1", NC_INT, {in_block, per_element});
    f.text_attribute(v.connect, "elem_type", "HEX8");
    v.elem_ss.resize(npatches);
    v.side_ss.resize(npatches);
    if (npatches > 0) {
        v.ss_status = f.var("ss_status", NC_INT, {num_side_sets});
        v.ss_prop = f.var("ss_prop1", NC_INT, {num_side_sets});
        f.text_attribute(v.ss_prop, "name", "ID");
        v.ss_names = f.var("ss_names", NC_CHAR, {num_side_sets, len_name});
        for (int p = 0; p < npatches; ++p) {
            v.elem_ss[p] = f.var(fmt::format("elem_ss{}", p + 1), NC_INT, {side_dims[p]});
            v.side_ss[p] = f.var(fmt::format("side_ss{}", p + 1), NC_INT, {side_dims[p]});
        }
    }
    f.check(nc_enddef(f.id()), "header");
    return v;
}

// Writes the variables' values: coordinates, the element block, the side sets.
void put_variables(NetcdfFile& f, const Variables& v, const BlockGrid& grid,
                   const std::vector<std::array<Id, 8>>& cells,
                   const std::vector<std::string>& patch_names, const SideSets& sets) {
    const int id = f.id();
    const int npatches = int(patch_names.size());
    f.check(nc_put_var_text(id, v.coord_names, name_block({"x", "y", "z"}).data()), "coor_names");
    std::vector<double> xyz(grid.points.size());
    for (int a = 0; a < 3; ++a) {
        for (size_t p = 0; p < grid.points.size(); ++p) xyz[p] = grid.points[p][a];
        f.check(nc_put_var_double(id, v.coord[a], xyz.data()), "coordinates");
    }
    const int one = 1;
    f.check(nc_put_var_int(id, v.eb_status, &one), "eb_status");
    f.check(nc_put_var_int(id, v.eb_prop, &one), "eb_prop1");
    f.check(nc_put_var_text(id, v.eb_names, name_block({"fluid"}).data()), "eb_names");
    std::vector<int> table(cells.size() * 8);
    for (size_t c = 0; c < cells.size(); ++c)
        for (int m = 0; m < 8; ++m) table[c * 8 + m] = int(cells[c][m] + 1);
    f.check(nc_put_var_int(id, v.connect, table.data()), "connect1");
    if (npatches > 0) {
        std::vector<int> status(npatches, 1), ids(npatches);
        for (int p = 0; p < npatches; ++p) ids[p] = p + 1;
        f.check(nc_put_var_int(id, v.ss_status, status.data()), "ss_status");
        f.check(nc_put_var_int(id, v.ss_prop, ids.data()), "ss_prop1");
        f.check(nc_put_var_text(id, v.ss_names, name_block(patch_names).data()), "ss_names");
        for (int p = 0; p < npatches; ++p) {
            f.check(nc_put_var_int(id, v.elem_ss[p], sets.element[p].data()), "elem_ss");
            f.check(nc_put_var_int(id, v.side_ss[p], sets.side[p].data()), "side_ss");
        }
    }
}

}  // namespace

void write_exodus_mesh(const BlockGrid& grid, const std::string& path) {
    const GridFaces faces = make_grid_faces(grid);
    const std::vector<std::array<Id, 8>> cells = cells_of(grid, path);
    const SideSets sets = side_sets(grid, faces, cells);
    NetcdfFile f(path);
    put_global_attributes(f, cells.size(), int(faces.patch_names.size()));
    const Variables v = define_variables(f, grid.points.size(), cells.size(), sets);
    put_variables(f, v, grid, cells, faces.patch_names, sets);
    f.close();
}

}  // namespace hexmesh
