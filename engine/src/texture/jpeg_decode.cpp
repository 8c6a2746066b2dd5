// JPEG textures through libjpeg-turbo. stb_image decoded a JPEG without quantization tables with
// tables it never set, so the same file gave different texels from run to run (found by
// fuzz_texture); libjpeg refuses a table that was not defined, and its warnings about corrupt
// data (a premature end of the entropy-coded data, a bad Huffman code, which it would decode on
// as zeros) are errors here: nothing is read wrongly in silence. libjpeg reports errors with
// longjmp, so the part that can jump is plain C-style code with no object that needs destroying.
#include "texture/jpeg_decode.hpp"

#include <jpeglib.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "common/try.hpp"

namespace facet {
namespace {

struct Errors {
  jpeg_error_mgr base;  // first: libjpeg hands out a pointer to it
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void on_error(j_common_ptr info) {
  auto* e = reinterpret_cast<Errors*>(info->err);
  (*info->err->format_message)(info, e->message);
  std::longjmp(e->jump, 1);
}

// Level -1: corrupt data libjpeg would decode on (as zeros); an error here. Others: trace output.
void on_message(j_common_ptr info, int level) {
  if (level < 0) on_error(info);
}
void no_output(j_common_ptr) {}

struct JpegHeader {
  int width = 0, height = 0, components = 0;
  bool progressive = false;
};

// Phase 1 reads the header into `header`; phase 2 the rows into `rgba`, sized by the caller.
// Returns false with `errors.message` set when libjpeg reports an error.
bool run(jpeg_decompress_struct& info, Errors& errors, const std::uint8_t* data, std::size_t size, JpegHeader& header,
         std::uint8_t* rgba, std::uint64_t max_bytes) {
  if (setjmp(errors.jump)) return false;
  if (!rgba) {
    jpeg_mem_src(&info, data, static_cast<unsigned long>(size));
    jpeg_read_header(&info, TRUE);
    header.width = static_cast<int>(info.image_width);
    header.height = static_cast<int>(info.image_height);
    header.components = info.num_components;
    header.progressive = info.progressive_mode != 0;
    return true;
  }
  if (max_bytes != 0) info.mem->max_memory_to_use = static_cast<long>(std::min<std::uint64_t>(max_bytes, 1ull << 62));
  info.out_color_space = JCS_EXT_RGBA;
  jpeg_start_decompress(&info);
  const std::size_t stride = 4 * static_cast<std::size_t>(info.output_width);
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = rgba + static_cast<std::size_t>(info.output_scanline) * stride;
    jpeg_read_scanlines(&info, &row, 1);
  }
  jpeg_finish_decompress(&info);
  return true;
}

}  // namespace

Result<PngPixels> decode_jpeg(std::span<const std::uint8_t> bytes, const std::string& source_name,
                              const std::function<Status(int, int, std::uint64_t)>& admit, std::uint64_t max_bytes) {
  auto fail = [&](ErrorCode code, const std::string& why) { return Status{code, "", source_name + ": " + why}; };
  jpeg_decompress_struct info;
  Errors errors;
  std::memset(&info, 0, sizeof info);
  info.err = jpeg_std_error(&errors.base);
  errors.base.error_exit = on_error;
  errors.base.emit_message = on_message;
  errors.base.output_message = no_output;
  errors.message[0] = '\0';
  jpeg_create_decompress(&info);
  struct Destroy {
    jpeg_decompress_struct* info;
    ~Destroy() { jpeg_destroy_decompress(info); }
  } destroy{&info};
  JpegHeader header;
  if (!run(info, errors, bytes.data(), bytes.size(), header, nullptr, 0)) {
    return fail(ErrorCode::parse_error, std::string("cannot read the JPEG header: ") + errors.message);
  }
  if (header.components != 1 && header.components != 3) {
    return fail(ErrorCode::unsupported, "a JPEG of " + std::to_string(header.components) +
                                            " components (CMYK?): facet reads grey and colour JPEGs");
  }
  // libjpeg's working memory: a few rows, or for a progressive file its coefficients (2 bytes per
  // sample, every component at full size in the worst case).
  const std::uint64_t samples = std::uint64_t(header.width) * std::uint64_t(header.height) * std::uint64_t(header.components);
  FACET_TRY(admit(header.width, header.height, header.progressive ? 2 * samples : 64 * std::uint64_t(header.width) * 4));
  PngPixels out;
  out.width = header.width;
  out.height = header.height;
  try {
    out.rgba.resize(4 * std::size_t(header.width) * std::size_t(header.height));
  } catch (const std::bad_alloc&) {
    return fail(ErrorCode::out_of_memory, "out of memory");
  }
  if (!run(info, errors, bytes.data(), bytes.size(), header, out.rgba.data(), max_bytes)) {
    const bool memory = std::strstr(errors.message, "nsufficient memory") != nullptr;
    return fail(memory ? ErrorCode::out_of_memory : ErrorCode::parse_error, std::string("cannot decode the JPEG: ") + errors.message);
  }
  return out;
}

}  // namespace facet
