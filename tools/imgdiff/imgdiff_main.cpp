// obvh_imgdiff: compares two images pixel by pixel (any format OpenImageIO reads: PNG, EXR, PPM...).
// Reports the largest and mean per-channel difference, PSNR and how many pixels differ by more
// than a tolerance; exits 1 when more pixels differ than allowed, 2 when an image cannot be read.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "image_compare.h"

namespace {

[[noreturn]] void usage() {
  std::fprintf(stderr,
               "usage: obvh_imgdiff A B [--tolerance T] [--max-differing N]\n"
               "  T: largest per-channel difference (0..1) that still counts as equal (default 0)\n"
               "  N: how many differing pixels are accepted (default 0)\n");
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) usage();
  double tolerance = 0.0;
  long maxDiffering = 0;
  for (int i = 3; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) usage();
    char* end = nullptr;
    if (arg == "--tolerance") tolerance = std::strtod(argv[++i], &end);
    else if (arg == "--max-differing") maxDiffering = std::strtol(argv[++i], &end, 10);
    else usage();
    if (*end != '\0' || tolerance < 0 || maxDiffering < 0) usage();
  }
  obvh::tools::Image a, b;
  std::string error;
  if (!obvh::tools::readImage(argv[1], a, error) || !obvh::tools::readImage(argv[2], b, error)) {
    std::fprintf(stderr, "obvh_imgdiff: %s\n", error.c_str());
    return 2;
  }
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) {
    std::fprintf(stderr, "obvh_imgdiff: sizes differ: %dx%dx%d vs %dx%dx%d\n", a.width, a.height, a.channels, b.width,
                 b.height, b.channels);
    return 1;
  }
  const obvh::tools::ImageDifference d = obvh::tools::compareImages(a, b, tolerance);
  std::printf("obvh_imgdiff: %zu of %zu pixels differ by more than %g; max error %g, mean error %.3g, PSNR %s dB; %ld allowed\n",
              d.differingPixels, d.pixels, tolerance, d.maxError, d.meanError,
              d.psnr == obvh::tools::kIdenticalPsnr ? "inf" : std::to_string(d.psnr).substr(0, 6).c_str(), maxDiffering);
  return long(d.differingPixels) <= maxDiffering ? 0 : 1;
}
