// A small software rasterizer for looking at bodies: orthographic views, z-buffered, flat Lambert
// shading, written as PNG. Used by `sscape synth --png` and by tools that need pictures.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::render {

struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;  // 3 bytes per pixel, rows top to bottom
    Image(int w, int h, uint8_t background = 255) : width(w), height(h), rgb(std::size_t(w) * h * 3, background) {}
    void set(int x, int y, uint8_t r, uint8_t g, uint8_t b);
};

enum class View { Front, Side, Back };  // Front: looking along -Z; Side: along -X (the body's left); Back: along +Z

struct Viewport {
    int x0, y0, width, height;  // pixel rectangle in the image
    float centre_x, centre_y, scale;  // world point at the rectangle's centre; pixels per metre
};

// Draws a triangle mesh (packed xyz, 3 indices per triangle) into a viewport, in one colour or,
// when triangle_colours is given (3 bytes per triangle), each triangle in its own.
void draw_mesh(Image& img, std::vector<float>& depth, const Viewport& vp, View view, const float* xyz,
               const uint32_t* triangles, uint32_t triangle_count, const uint8_t colour[3], const uint8_t* triangle_colours = nullptr);

// The direction from the body towards the viewer of a view (for culling marks on the far side).
void view_direction(View view, float out[3]);

// Marks a point (e.g. a landmark) with a filled disc drawn over everything.
void draw_point(Image& img, const Viewport& vp, View view, const float* p, int radius, const uint8_t colour[3]);

// As draw_point, but only inside the viewport and where the point lies on the mesh already drawn
// there, not hidden behind it (depth buffer of draw_mesh, tolerance in metres). Returns whether
// it was drawn.
bool draw_visible_point(Image& img, const std::vector<float>& depth, const Viewport& vp, View view, const float* p,
                        int radius, const uint8_t colour[3], float tolerance = 0.01f);

// Writes the image as an 8-bit RGB PNG (temporary file + rename). Throws ssc::Error(SSC_ERROR_IO).
void write_png(const std::string& path, const Image& img);

}  // namespace ssc::render
