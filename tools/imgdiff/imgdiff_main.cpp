// obvh_imgdiff: compares two images pixel by pixel (any format OpenImageIO reads, e.g. PPM or PNG).
// Prints how many pixels differ by more than a tolerance and exits 1 when more than allowed do.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;
};

bool load(const std::string& path, Image& image) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::fprintf(stderr, "obvh_imgdiff: cannot open '%s': %s\n", path.c_str(), OIIO::geterror().c_str());
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  image.width = spec.width, image.height = spec.height, image.channels = spec.nchannels;
  image.pixels.resize(size_t(image.width) * image.height * image.channels);
  if (!in->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    std::fprintf(stderr, "obvh_imgdiff: cannot read '%s': %s\n", path.c_str(), in->geterror().c_str());
    return false;
  }
  return true;
}

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
  Image a, b;
  if (!load(argv[1], a) || !load(argv[2], b)) return 2;
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) {
    std::fprintf(stderr, "obvh_imgdiff: sizes differ: %dx%dx%d vs %dx%dx%d\n", a.width, a.height, a.channels, b.width,
                 b.height, b.channels);
    return 1;
  }
  long differing = 0;
  double largest = 0.0;
  const size_t pixelCount = size_t(a.width) * a.height;
  for (size_t p = 0; p < pixelCount; ++p) {
    double d = 0.0;
    for (int c = 0; c < a.channels; ++c)
      d = std::max(d, double(std::fabs(a.pixels[p * a.channels + c] - b.pixels[p * a.channels + c])));
    largest = std::max(largest, d);
    if (d > tolerance) ++differing;
  }
  std::printf("obvh_imgdiff: %ld of %zu pixels differ by more than %g (largest difference %g); %ld allowed\n",
              differing, pixelCount, tolerance, largest, maxDiffering);
  return differing <= maxDiffering ? 0 : 1;
}
