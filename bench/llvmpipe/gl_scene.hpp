// facet's scenes drawn by OpenGL 2.1's fixed function, for the llvmpipe comparison
// (facet_vs_llvmpipe.cpp): gl_scene.cpp holds the translation.
#pragma once

#include <GL/gl.h>

#include <string>
#include <vector>

#include "facet/facet.hpp"

namespace gl_compare {

// Whether the scene has textures, vertex colours, blending, alpha test or fog (held to the
// surfaces target).
bool has_surfaces(const facet::Scene& s);

// Lights for the comparison: a directional key light, then point and GL spot lights around.
std::vector<facet::Light> light_set(int count, const facet::Vec3& centre, float radius);

// The scene's bounding sphere (world space), to place lights.
void bounds(const facet::Scene& s, facet::Vec3& centre, float& radius);

// Every reason the scene cannot be drawn by GL 2.1 here, joined with "; " (empty: none), so that a
// scene's author learns all of them from one run. phong: --shading phong.
std::string gl_incompatibility(const facet::Scene& s, bool phong);

// GL objects made once per scene, before timing: textures (facet's levels) and RGBA vertex colours
// whose alpha is the material's (GL takes the diffuse alpha from the colour under glColorMaterial).
struct GlScene {
  std::vector<GLuint> textures;
  std::vector<GLuint> emission;             // per material: its emission unit's texture, 0: none
  std::vector<GLuint> environment;          // per material: its environment unit's texture, 0: none
  std::vector<std::vector<float>> colours;  // per object, empty without vertex colours
  std::vector<std::size_t> order;           // the objects in facet's drawing order (facet::draw_order)
  GLuint projector = 0;                     // --shading phong: the projector's picture (unit 3), 0: none
  std::vector<std::vector<float>> dot3;     // --shading phong: per object, the tangent-space light vector as RGBA colours
};

// Makes the scene's GL objects (before timing) and frees them.
GlScene gl_prepare(const facet::Scene& s, bool phong);
void gl_release(GlScene& g);

// Draws the scene with fixed-function OpenGL into the current OSMesa buffer.
void gl_draw(const facet::Scene& s, const GlScene& g, int w, int h);

}  // namespace gl_compare
