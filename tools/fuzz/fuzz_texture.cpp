// Fuzzes the image decoders (PNG through libpng; JPEG, TGA and BMP through stb): any bytes are
// refused with a message that gives a reason and holds no control character, or decode to a
// valid texture, to the same texels every time (an uninitialised palette once made them vary).
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace facet;
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
