// Fuzzes the image decoders (PNG through libpng; JPEG, TGA and BMP through stb) and the
// environment pictures' (Radiance .hdr read by facet, OpenEXR, PNG and JPEG): any bytes are
// refused with a message that gives a reason and holds no control character, or decode to a
// valid texture (a valid environment picture of finite texels >= 0), the same every time (an
// uninitialised palette once made texels vary).
#include "fuzz_support.hpp"

namespace {

void check_message(const facet::Status& s) {
  const std::string& m = s.message();
  if (m.empty() || m.back() == ' ' || m.back() == ':') facet::fuzz::broken("a decode error without a reason");
  for (const char c : m)
    if (static_cast<unsigned char>(c) < 0x20) facet::fuzz::broken("a control character in a message");
}

void environment_picture(std::span<const std::uint8_t> bytes) {
  using namespace facet;
  const Result<EnvironmentLight> a = decode_environment_image(bytes, "fuzz.hdr", 64u << 20);
  if (!a.ok()) return check_message(a.status());
  if (!validate_environment_light(*a).ok()) fuzz::broken("decode_environment_image returned an invalid picture");
  for (const float v : a->rgb)
    if (!(v >= 0.0f && v <= 3.4e38f)) fuzz::broken("an environment texel negative, infinite or NaN");
  const Result<EnvironmentLight> b = decode_environment_image(bytes, "fuzz.hdr", 64u << 20);
  if (!b.ok() || b->rgb != a->rgb) fuzz::broken("the same bytes decoded to different environment texels");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace facet;
  environment_picture(std::span<const std::uint8_t>(data, size));
  TextureOptions options;
  options.memory_budget_bytes = 64u << 20;
  options.filter = (size > 0 && (data[size - 1] & 1)) ? TextureFilter::trilinear : TextureFilter::nearest;
  const std::span<const std::uint8_t> bytes(data, size);
  const Result<Texture> a = decode_texture(bytes, "fuzz.img", "t", options);
  if (!a.ok()) {
    const std::string& m = a.status().message();
    if (m.empty() || m.back() == ' ' || m.back() == ':') fuzz::broken("a decode error without a reason");
    for (const char c : m)
      if (static_cast<unsigned char>(c) < 0x20) fuzz::broken("a control character in a message");
    return 0;
  }
  if (!validate_texture(*a).ok()) fuzz::broken("decode_texture returned an invalid texture");
  const Result<Texture> b = decode_texture(bytes, "fuzz.img", "t", options);
  if (!b.ok() || b->texels != a->texels) fuzz::broken("the same bytes decoded to different texels");
  return 0;
}
