#include "layout_configs.h"

#include "traversal/oriented_wide_traversal.h"

namespace obvh::tools {
namespace {

LayoutConfig make(const char* name, const char* deviceConfig, AccelLayout layout, ObbSplit split = ObbSplit::AabbSah,
                  int clusters = 0, int obbWidth = fastestOrientedWidth()) {
  LayoutConfig c{name, deviceConfig, BuildOptions{}};
  c.options.obbWidth = obbWidth;
  c.options.layout = layout;
  c.options.maxLeafSize = 0;  // as a device would: the layout's default
  c.options.obbSplit = split;
  c.options.obbClusters = clusters;
  c.options.obbPalette = clusters > 0 ? 0 : kDefaultObbPalette;  // as a device would
  return c;
}

}  // namespace

const std::vector<LayoutConfig>& layoutConfigs() {
  static const std::vector<LayoutConfig> configs = {
      make("aabb", "accel=bvh2", AccelLayout::Bvh2),
      make("aabb-bvh8", "accel=bvh8", AccelLayout::Bvh8),
      make("obb", "accel=obb", AccelLayout::Obb),  // the axis-aligned SAH tree traced with oriented boxes
      make("obb-binary", "accel=obb,obb_width=2", AccelLayout::Obb, ObbSplit::AabbSah, 0, 2),
      [] { auto c = make("obb-greedy", "accel=obb,collapse=greedy", AccelLayout::Obb); c.options.collapse = WideCollapse::Greedy; return c; }(),
      make("obb-w4", "accel=obb,obb_width=4", AccelLayout::Obb, ObbSplit::AabbSah, 0, 4),
      make("obb-midpoint", "accel=obb,obb_split=midpoint", AccelLayout::Obb, ObbSplit::Midpoint),
      make("obb-median", "accel=obb,obb_split=median", AccelLayout::Obb, ObbSplit::Median),
      make("obb-sah", "accel=obb,obb_split=sah", AccelLayout::Obb, ObbSplit::Sah),
      [] { auto c = make("obb-pca", "accel=obb,obb_fit=pca", AccelLayout::Obb); c.options.obbFit = ObbFit::Pca; return c; }(),
      make("hybrid", "accel=hybrid", AccelLayout::Hybrid),
      make("hybrid-binary", "accel=hybrid,obb_width=2", AccelLayout::Hybrid, ObbSplit::AabbSah, 0, 2),
      make("hybrid-sah", "accel=hybrid,obb_split=sah", AccelLayout::Hybrid, ObbSplit::Sah),
      [] { auto c = make("hybrid-pca", "accel=hybrid,obb_fit=pca", AccelLayout::Hybrid); c.options.obbFit = ObbFit::Pca; return c; }(),
      make("obb-k1000", "accel=obb,obb_clusters=1000", AccelLayout::Obb, ObbSplit::AabbSah, 1000),
      make("hybrid-k1000", "accel=hybrid,obb_clusters=1000", AccelLayout::Hybrid, ObbSplit::AabbSah, 1000),
      [] { auto c = make("obb-p0", "accel=obb,obb_palette=0", AccelLayout::Obb); c.options.obbPalette = 0; return c; }(),
      [] { auto c = make("hybrid-p0", "accel=hybrid,obb_palette=0", AccelLayout::Hybrid); c.options.obbPalette = 0; return c; }(),
  };
  return configs;
}

const LayoutConfig* findLayoutConfig(const std::string& name) {
  for (const LayoutConfig& c : layoutConfigs())
    if (c.name == name) return &c;
  return nullptr;
}

}  // namespace obvh::tools
