#include "iilfm/image_files.hpp"

// jpeglib.h uses FILE without including <cstdio>: it must come first.
// clang-format off
#include <cstdio>
#include <jpeglib.h>
// clang-format on
#include <png.h>
#include <tiffio.h>

#include <cctype>
#include <cmath>
#include <csetjmp>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

#include "iilfm/error.hpp"

namespace iilfm {
namespace {

constexpr double kMetresPerInch = 0.0254;

bool eight_bit_gray_or_bgr(const cv::Mat& image) {
  return !image.empty() && image.depth() == CV_8U &&
         (image.channels() == 1 || image.channels() == 3);
}

// ---- PNG (libpng; errors come back through setjmp, as libpng requires of a C++ caller) ----

void append_png_bytes(png_structp png, png_bytep data, png_size_t size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + size);
}

void flush_nothing(png_structp) {}

struct PngReadSource {
  const std::vector<std::uint8_t>* bytes;
  std::size_t at = 0;
};

void read_png_bytes(png_structp png, png_bytep data, png_size_t size) {
  auto* source = static_cast<PngReadSource*>(png_get_io_ptr(png));
  if (size > source->bytes->size() - source->at) png_error(png, "file ends inside the image");
  std::memcpy(data, source->bytes->data() + source->at, size);
  source->at += size;
}

// libpng's messages are kept for the caller's error, not printed.
void keep_png_error(png_structp png, png_const_charp message) {
  auto* problem = static_cast<std::string*>(png_get_error_ptr(png));
  if (problem) *problem = message;
  png_longjmp(png, 1);
}
void ignore_png_warning(png_structp, png_const_charp) {}

// libpng reports errors by longjmp to the last setjmp: each step that can fail arms its own, in a
// function whose locals do not change after it, so nothing is left half-made by the jump.
bool read_png_header(png_structp png, png_infop info, PngReadSource* source) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_read_fn(png, source, read_png_bytes);
  png_read_info(png, info);
  return true;
}

bool read_png_rows(png_structp png, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, nullptr);
  return true;
}

struct PngReader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngReader() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

// The values of a gray PNG (8 or 16 bits; 1, 2 or 4 bits widened to 8), else a problem.
cv::Mat decode_png(const std::vector<std::uint8_t>& bytes, std::string& problem) {
  PngReader reader;
  reader.png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, &problem, keep_png_error, ignore_png_warning);
  if (reader.png) reader.info = png_create_info_struct(reader.png);
  if (!reader.info) {
    problem = "out of memory";
    return {};
  }
  PngReadSource source{&bytes};
  if (!read_png_header(reader.png, reader.info, &source)) return {};
  const png_uint_32 width = png_get_image_width(reader.png, reader.info),
                    height = png_get_image_height(reader.png, reader.info);
  const int depth = png_get_bit_depth(reader.png, reader.info),
            type = png_get_color_type(reader.png, reader.info);
  if (type != PNG_COLOR_TYPE_GRAY) {
    problem = type == PNG_COLOR_TYPE_GRAY_ALPHA ? "gray with alpha"
              : type == PNG_COLOR_TYPE_PALETTE  ? "a palette image"
                                                : "a colour image";
    return {};
  }
  if (width > (1u << 20) || height > (1u << 20)) {
    problem = "image too large";
    return {};
  }
  if (depth < 8) png_set_expand_gray_1_2_4_to_8(reader.png);
  if (depth == 16) png_set_swap(reader.png);  // PNG stores 16-bit values big-endian
  cv::Mat image(static_cast<int>(height), static_cast<int>(width),
                depth == 16 ? CV_16UC1 : CV_8UC1);
  std::vector<png_bytep> rows(height);
  for (png_uint_32 r = 0; r < height; ++r) rows[r] = image.ptr(static_cast<int>(r));
  if (!read_png_rows(reader.png, rows.data())) return {};
  return image;
}

// ---- JPEG (libjpeg: its default error handler exits the process, so it is replaced) ----

struct JpegErrors {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
};

void jpeg_error_jump(j_common_ptr info) {
  std::longjmp(reinterpret_cast<JpegErrors*>(info->err)->jump, 1);
}

// As for libpng: the setjmp in a function whose locals do not change after it.
bool compress_jpeg(jpeg_compress_struct* jpeg, JpegErrors* errors, const cv::Mat& image,
                   int quality, unsigned char** buffer, unsigned long* size) {
  if (setjmp(errors->jump)) return false;
  jpeg_mem_dest(jpeg, buffer, size);
  jpeg->image_width = static_cast<JDIMENSION>(image.cols);
  jpeg->image_height = static_cast<JDIMENSION>(image.rows);
  jpeg->input_components = image.channels();
  jpeg->in_color_space = image.channels() == 1 ? JCS_GRAYSCALE : JCS_EXT_BGR;
  jpeg_set_defaults(jpeg);
  jpeg_set_quality(jpeg, quality, TRUE);
  jpeg_start_compress(jpeg, TRUE);
  while (jpeg->next_scanline < jpeg->image_height) {
    auto row = const_cast<JSAMPROW>(image.ptr(static_cast<int>(jpeg->next_scanline)));
    jpeg_write_scanlines(jpeg, &row, 1);
  }
  jpeg_finish_compress(jpeg);
  return true;
}

// ---- PGM ----

// The next header value of a PGM (blanks and # comments between values).
bool pgm_value(const std::vector<std::uint8_t>& bytes, std::size_t& at, unsigned long& value) {
  while (at < bytes.size()) {
    if (bytes[at] == '#') {
      while (at < bytes.size() && bytes[at] != '\n') ++at;
    } else if (std::isspace(bytes[at])) {
      ++at;
    } else {
      break;
    }
  }
  if (at >= bytes.size() || !std::isdigit(bytes[at])) return false;
  value = 0;
  while (at < bytes.size() && std::isdigit(bytes[at]) && value < 1'000'000'000)
    value = value * 10 + (bytes[at++] - '0');
  return true;
}

cv::Mat decode_pgm(const std::vector<std::uint8_t>& bytes, std::string& problem) {
  const bool binary = bytes[1] == '5';
  std::size_t at = 2;
  unsigned long width, height, maxval;
  if (!pgm_value(bytes, at, width) || !pgm_value(bytes, at, height) ||
      !pgm_value(bytes, at, maxval) || width == 0 || height == 0 || maxval == 0 || maxval > 65535 ||
      width > 1u << 20 || height > 1u << 20) {
    problem = "bad PGM header";
    return {};
  }
  const bool wide = maxval > 255;
  cv::Mat image(static_cast<int>(height), static_cast<int>(width), wide ? CV_16UC1 : CV_8UC1);
  const std::size_t samples = width * height;
  if (binary) {
    ++at;  // the single blank after maxval
    const std::size_t size = samples * (wide ? 2 : 1);
    if (at > bytes.size() || bytes.size() - at < size) {
      problem = "PGM data ends early";
      return {};
    }
    for (std::size_t i = 0; i < samples; ++i) {
      if (wide) {
        image.ptr<std::uint16_t>()[i] =  // big-endian, as the format says
            static_cast<std::uint16_t>(bytes[at + 2 * i] << 8 | bytes[at + 2 * i + 1]);
      } else {
        image.ptr<std::uint8_t>()[i] = bytes[at + i];
      }
    }
    return image;
  }
  for (std::size_t i = 0; i < samples; ++i) {
    unsigned long value;
    if (!pgm_value(bytes, at, value) || value > maxval) {
      problem = "PGM values end early or exceed the maximum";
      return {};
    }
    if (wide)
      image.ptr<std::uint16_t>()[i] = static_cast<std::uint16_t>(value);
    else
      image.ptr<std::uint8_t>()[i] = static_cast<std::uint8_t>(value);
  }
  return image;
}

// ---- TIFF (libtiff, strips of one 8- or 16-bit unsigned sample per pixel) ----

thread_local std::string tiff_problem;

void keep_tiff_error(const char*, const char* format, va_list args) {
  char text[256];
  std::vsnprintf(text, sizeof text, format, args);
  tiff_problem = text;
}
void ignore_tiff_warning(const char*, const char*, va_list) {}

cv::Mat decode_tiff(const std::string& path, std::string& problem) {
  TIFFSetErrorHandler(keep_tiff_error);
  TIFFSetWarningHandler(ignore_tiff_warning);
  tiff_problem.clear();
  TIFF* tiff = TIFFOpen(path.c_str(), "r");
  if (!tiff) {
    problem = tiff_problem.empty() ? "not a TIFF file" : tiff_problem;
    return {};
  }
  std::uint32_t width = 0, height = 0;
  std::uint16_t samples = 1, bits = 1, format = SAMPLEFORMAT_UINT;
  TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &height);
  TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLESPERPIXEL, &samples);
  TIFFGetFieldDefaulted(tiff, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLEFORMAT, &format);
  cv::Mat image;
  if (samples != 1) {
    problem = std::to_string(samples) + " samples per pixel";
  } else if ((bits != 8 && bits != 16) || format != SAMPLEFORMAT_UINT) {
    problem = std::to_string(bits) + "-bit " + (format == SAMPLEFORMAT_UINT ? "" : "non-integer ") +
              "samples";
  } else if (TIFFIsTiled(tiff)) {
    problem = "tiled TIFF (only strips are read)";
  } else if (width == 0 || height == 0 || width > 1u << 20 || height > 1u << 20) {
    problem = "bad image size";
  } else {
    image.create(static_cast<int>(height), static_cast<int>(width),
                 bits == 16 ? CV_16UC1 : CV_8UC1);
    for (std::uint32_t r = 0; r < height; ++r) {
      if (TIFFReadScanline(tiff, image.ptr(static_cast<int>(r)), r, 0) < 0) {
        problem = tiff_problem.empty() ? "cannot read row " + std::to_string(r) : tiff_problem;
        image.release();
        break;
      }
    }
  }
  TIFFClose(tiff);
  return image;
}

std::vector<std::uint8_t> whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path, "cannot open the image");
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

struct PngWriter {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngWriter() { png_destroy_write_struct(&png, info ? &info : nullptr); }
};

bool write_png(png_structp png, png_infop info, const cv::Mat& image, double dpi,
               std::vector<std::uint8_t>* out, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, out, append_png_bytes, flush_nothing);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols),
               static_cast<png_uint_32>(image.rows), 8,
               image.channels() == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (dpi > 0) {
    const auto per_metre = static_cast<png_uint_32>(std::lround(dpi / kMetresPerInch));
    png_set_pHYs(png, info, per_metre, per_metre, PNG_RESOLUTION_METER);
  }
  png_write_info(png, info);
  if (image.channels() == 3) png_set_bgr(png);  // OpenCV's channel order
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

}  // namespace

std::vector<std::uint8_t> encode_png(const cv::Mat& image, double dpi) {
  if (!eight_bit_gray_or_bgr(image)) return {};
  PngWriter writer;
  writer.png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, keep_png_error, ignore_png_warning);
  if (writer.png) writer.info = png_create_info_struct(writer.png);
  if (!writer.info) return {};
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.rows));
  for (int r = 0; r < image.rows; ++r)
    rows[static_cast<std::size_t>(r)] = const_cast<png_bytep>(image.ptr(r));
  std::vector<std::uint8_t> out;
  if (!write_png(writer.png, writer.info, image, dpi, &out, rows.data())) return {};
  return out;
}

std::vector<std::uint8_t> encode_jpeg(const cv::Mat& image, int quality) {
  if (!eight_bit_gray_or_bgr(image)) return {};
  jpeg_compress_struct jpeg{};
  JpegErrors errors{};
  jpeg.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = jpeg_error_jump;
  jpeg_create_compress(&jpeg);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  const bool done = compress_jpeg(&jpeg, &errors, image, quality, &buffer, &size);
  std::vector<std::uint8_t> out;
  if (done) out.assign(buffer, buffer + size);
  jpeg_destroy_compress(&jpeg);
  std::free(buffer);
  return out;
}

void write_bytes_to_file(const std::string& path, const std::vector<std::uint8_t>& bytes,
                         const std::string& what) {
  std::ofstream file(path, std::ios::binary);
  if (!file ||
      !file.write(reinterpret_cast<const char*>(bytes.data()),
                  static_cast<std::streamsize>(bytes.size())) ||
      !file.flush())
    throw file_error(path, "cannot write " + what);
}

cv::Mat read_intensity_image(const std::string& path) {
  const std::vector<std::uint8_t> bytes = whole_file(path);
  std::string problem;
  cv::Mat image;
  static constexpr std::uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), kPng, 8) == 0) {
    image = decode_png(bytes, problem);
  } else if (bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '5' || bytes[1] == '2')) {
    image = decode_pgm(bytes, problem);
  } else if (bytes.size() >= 4 && ((bytes[0] == 'I' && bytes[1] == 'I' && bytes[2] == 42) ||
                                   (bytes[0] == 'M' && bytes[1] == 'M' && bytes[3] == 42))) {
    image = decode_tiff(path, problem);
  } else {
    problem = "not a PNG, PGM or TIFF file";
  }
  if (image.empty())
    throw file_error(path, "cannot read the image: " + (problem.empty() ? "unreadable" : problem) +
                               " (expected a single-channel 8- or 16-bit PNG, PGM or TIFF)");
  return image;
}

}  // namespace iilfm
