// Internal: the surroundings behind the model (Scene::background == environment) as the camera
// pass's clear value. Every pixel (each of its samples) starts as the radiance seen through its
// centre instead of the clear colour, so blended surfaces blend over it and multisampled edges
// resolve against it exactly as they would against a clear colour; the display transform then
// exposes and tone-maps it with the surfaces.
#pragma once

#include <Eigen/Core>

#include "facet/environment_light.hpp"
#include "facet/image.hpp"
#include "io/srgb.hpp"

namespace facet::lighting {
class ImageLight;
}

namespace facet::tile {

struct TileRect;
struct TileBuffers;

struct Backdrop {
  const lighting::ImageLight* light = nullptr;
  float intensity = 1.0f;
  // Pixel (x, y) of the pass -> a direction in the light's frame (not unit): ray (x + 1/2, y + 1/2, 1).
  double ray[9] = {};
};

// The backdrop of a camera (`view`, `projection`) over a width x height image, from the prepared
// light of `env`.
Backdrop make_backdrop(const lighting::ImageLight& light, const EnvironmentLight& env, const Eigen::Matrix4d& view,
                       const Eigen::Matrix4d& projection, int width, int height);

// Pixel (x, y)'s colour: intensity times the picture along its ray (bilinear), alpha 1.
void backdrop_pixel(const Backdrop& b, int x, int y, float rgba[4]);

// Every pixel and sample of the tile's planes: the backdrop, at depth `far`.
void fill_backdrop(const Backdrop& b, const TileRect& rect, TileBuffers& tile, float far);

// A tile no triangle touches: the backdrop straight into the views (converted as resolve_tile
// converts the planes) and far depth (`far_depth`, in the output's convention).
void resolve_backdrop_tile(const Backdrop& b, const SrgbTable* srgb, const TileRect& rect, const ImageView& color,
                           const DepthView* depth, float far_depth);

}  // namespace facet::tile
