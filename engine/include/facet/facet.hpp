// Umbrella header: the whole public C++ API of facet.
#pragma once

#include "facet/camera.hpp"
#include "facet/image.hpp"
#include "facet/light.hpp"
#include "facet/lighting.hpp"
#include "facet/material.hpp"
#include "facet/bake.hpp"
#include "facet/lightmap.hpp"
#include "facet/mesh.hpp"
#include "facet/model.hpp"
#include "facet/render.hpp"
#include "facet/scene.hpp"
#include "facet/scene_file.hpp"
#include "facet/status.hpp"
#include "facet/texture.hpp"
#include "facet/types.hpp"
#include "facet/version.hpp"
