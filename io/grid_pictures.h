// Pictures of a grid drawn by the program itself, without a display: its wall from four
// directions and plane cuts through its cells, each cell coloured by a value (its scaled
// Jacobian), as PNG images.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/types.h"

namespace hexmesh {

// An orthographic view: a model point's pixel (x to the right, y down) and its depth
// (larger is nearer the viewer).
struct View {
    Vec3 centre = Vec3::Zero();
    Vec3 right = Vec3::UnitX(), up = Vec3::UnitY(), towards_viewer = Vec3::UnitZ();
    double pixels_per_unit = 1;
    int width = 0, height = 0;

    // Looks along -towards_viewer at `box`, which fills the picture but a margin.
    static View framing(const Box3& box, const Vec3& towards_viewer, const Vec3& up, int width,
                        int height);
    Vec3 pixel(const Vec3& p) const;  // (x, y, depth)
};

struct Picture {
    std::string title;
    View view;
    bool cut = false;  // a plane cut (else a view of the wall)
    std::string png;   // the image file's bytes
};

// Colours of a value over [lo, hi]: red at lo through orange and yellow to green and blue at
// hi; a value under lo (an inverted cell) magenta.
std::array<unsigned char, 3> value_colour(double value, double lo, double hi);

// Draws the wall quads and the cells given to it into every picture at once, so that a grid
// can be drawn block by block as it is made: four views of the wall framing `wall_box` and
// plane cuts (x, y, z through the centre of `wall_box`, framed on it; z through the centre
// of `domain_box`, framed on that, when the domain is much larger, as an exterior grid's is).
class GridPictures {
  public:
    GridPictures(const Box3& wall_box, const Box3& domain_box, double lo, double hi,
                 int size = 640);
    ~GridPictures();
    GridPictures(GridPictures&&) noexcept;
    GridPictures& operator=(GridPictures&&) noexcept;

    // A wall face (a triangle when q[3] == q[2]) and a value.
    void add_wall_face(const std::array<Vec3, 4>& q, double value);
    // A hex (8 corners in VTK order) or a tet (4) and its value: drawn where a cut crosses it.
    void add_cell(const Vec3* corners, int count, double value);
    // The block's cells (values[c], c in block order i fastest) and its faces whose patch is
    // "wall" (every boundary face of the block instead when `all_boundary`).
    void add_block(const BlockGrid& grid, const Block& block, const double* values,
                   bool all_boundary = false);

    std::vector<Picture> pictures() const;  // PNG-encoded

    // What has been drawn, as bytes for another process; merge() draws another GridPictures'
    // pack() (the same frames) into this one, the nearer of the two at each pixel: the
    // blocks of one grid drawn by several processes, then put together. set_order(n) before
    // drawing block n (several processes, each drawing some blocks in increasing n) makes
    // merge() break depth ties as one process drawing every block in order does, so the
    // pictures are the same.
    void set_order(std::uint32_t order);
    std::string pack() const;
    void merge(const std::string& packed);

  private:
    struct Canvas;
    std::vector<Canvas> wall_;
    std::vector<Canvas> cuts_;
    double lo_, hi_;
};

}  // namespace hexmesh
