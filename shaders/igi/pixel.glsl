// Where a pixel stands in IGI's gather grid (crates/platoon-core/src/igi: IgiOptions::grid).

// The grid cell of the pixel along one axis of n pixels, and whether the pixel is the one that
// gathers for it: the cell's centre, or the frame's last pixel for a cell the edge cuts.
uint igi_cell(uint x, uint n, out bool gathers) {
#ifdef IGI_DOWNSAMPLED
    uint k = igi_downsample();
    uint c = x / k;
    gathers = x == min(c * k + k / 2u, n - 1u);
    return c;
#else
    gathers = true;
    return x;
#endif
}

bool igi_gathers(uvec2 pixel) {
    bool gx, gy;
    igi_cell(pixel.x, F.dims.x, gx);
    igi_cell(pixel.y, F.dims.y, gy);
    return gx && gy;
}

// The VPL subset the pixel gathers: with IGI_INTERLEAVED one of the tile's, by the position of
// the pixel's cell in its tile; else the one subset of all.
uint igi_subset(uvec2 pixel) {
#ifdef IGI_INTERLEAVED
    bool g;
    uvec2 cell = uvec2(igi_cell(pixel.x, F.dims.x, g), igi_cell(pixel.y, F.dims.y, g));
    return (cell.x % igi_tile().x) + igi_tile().x * (cell.y % igi_tile().y);
#else
    return 0u;
#endif
}

uint igi_subsets() {
#ifdef IGI_INTERLEAVED
    return igi_tile().x * igi_tile().y;
#else
    return 1u;
#endif
}
