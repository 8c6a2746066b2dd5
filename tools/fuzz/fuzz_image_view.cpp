// Fuzzes image-view validation: any description is either refused, or, when accepted and small
// enough to allocate here, rendered into a buffer of exactly that description without a byte
// outside it written.
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace facet;
  fuzz::Bytes in(data, size);
  ImageView v;
  v.width = in.take<std::int32_t>();
  v.height = in.take<std::int32_t>();
  v.stride_bytes = in.take<std::uint32_t>();
  const std::uint8_t flags = in.take<std::uint8_t>();
  v.format = static_cast<PixelFormat>(flags % 4);  // 3 is not a format
  v.y_up = (flags & 4) != 0;
  std::uint8_t dummy = 0;
  v.data = (flags & 8) ? nullptr : &dummy;
  const Status st = validate_image_view(v);
  if (!st.ok()) {
    if (st.field().empty()) fuzz::broken("a refused view without a field name");
    Renderer renderer;
    if (renderer.render(make_default_scene(), {}, v).ok()) fuzz::broken("render accepted a refused view");
    return 0;
  }
  const std::size_t pixel_bytes = static_cast<std::size_t>(v.width) * bytes_per_pixel(v.format);
  if (static_cast<std::size_t>(v.height) * v.stride_bytes > (1u << 20)) return 0;  // valid, too big to try here
  fuzz::GuardedImage image(v.width, v.height, v.format, v.stride_bytes - pixel_bytes, v.y_up);
  Scene s = make_default_scene();
  RenderOptions options;
  options.threads = 1;
  Renderer renderer;
  if (!renderer.render(s, options, image.view()).ok()) fuzz::broken("a valid view failed to render");
  image.check();
  return 0;
}
