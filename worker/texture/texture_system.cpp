#include "texture/texture_system.h"

#include <unistd.h>

// Before OIIO's headers: they define bswap_32 and bswap_64 in a way protobuf's (which these
// include) then fails to compile against.
#include "contract/failure.h"
#include "contract/rules.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <atomic>
#include <cmath>
#include <system_error>

namespace farm {
namespace {

namespace oiio = OIIO;

// Bumped when the prepared form changes, so that files of an older worker are not read.
constexpr const char* kPreparedVersion = "v2";

float SrgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

// The source as RGBA floats or its own type: grey replicated, alpha 1 where it has none.
// The fourth channel is not named "A": OIIO would then take it for associated alpha and
// premultiply (in make_texture or the lookups), where glTF's base colour does not depend on
// its alpha; as an ordinary channel, colour and alpha are each filtered on their own.
oiio::ImageBuf ToRgba(const oiio::ImageBuf& in) {
  const int n = in.nchannels();
  const int order[4] = {0, n >= 3 ? 1 : 0, n >= 3 ? 2 : 0, n == 2 ? 1 : (n >= 4 ? 3 : -1)};
  const float fill[4] = {0, 0, 0, 1};
  const std::string names[4] = {"R", "G", "B", "Opacity"};
  oiio::ImageBuf rgba = oiio::ImageBufAlgo::channels(in, 4, order, fill, names);
  rgba.specmod().alpha_channel = -1;
  return rgba;
}

std::string Hex(const std::string& digest) { return digest.substr(digest.find(':') + 1); }

oiio::TextureOpt::Wrap OiioWrap(TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::kRepeat: return oiio::TextureOpt::WrapPeriodic;
    case TextureWrap::kClamp: return oiio::TextureOpt::WrapClamp;
    case TextureWrap::kMirror: return oiio::TextureOpt::WrapMirror;
  }
  return oiio::TextureOpt::WrapPeriodic;
}

// Whether the file's values are sRGB, from its header, which must be an image's of at most
// max_texture_pixels pixels.
bool DecodesSrgb(const std::filesystem::path& source, const std::string& digest, TextureUse use,
                 TextureEncoding encoding) {
  const std::string name = "texture " + digest;
  std::unique_ptr<oiio::ImageInput> in = oiio::ImageInput::open(source.string());
  if (!in) throw BadInputError(name + " is not an image OpenImageIO reads: " + oiio::geterror());
  const oiio::ImageSpec& spec = in->spec();
  const std::uint64_t pixels = std::uint64_t(spec.width) * std::uint64_t(spec.height);
  const std::uint64_t limit = contract::SceneLimits().max_texture_pixels();
  if (pixels > limit || spec.depth > 1)
    throw BadInputError(name + " has " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                        " pixels, more than max_texture_pixels " + std::to_string(limit));
  if (encoding != TextureEncoding::kByUse) return encoding == TextureEncoding::kSrgb;
  return use == TextureUse::kColor && !spec.format.is_floating_point();
}

// The file's pixels, converted and laid out for the texture system, written as a tiled
// MIP-mapped file at `out` through a temporary file renamed into place.
void WritePrepared(const std::filesystem::path& source, const std::string& digest, bool srgb,
                   const std::filesystem::path& out) {
  const std::string name = "texture " + digest;
  oiio::ImageSpec read_config;
  read_config.attribute("oiio:UnassociatedAlpha", 1);  // glTF's colour does not depend on alpha
  oiio::ImageBuf in(source.string(), 0, 0, nullptr, &read_config);
  if (!in.read(0, 0, true, srgb ? oiio::TypeDesc::FLOAT : oiio::TypeDesc::UNKNOWN))
    throw BadInputError(name + " cannot be read: " + in.geterror());
  oiio::ImageBuf rgba = ToRgba(in);
  if (rgba.has_error()) throw BadInputError(name + ": " + rgba.geterror());
  if (srgb) {
    for (oiio::ImageBuf::Iterator<float> p(rgba); !p.done(); ++p)
      for (int c = 0; c < 3; ++c) p[c] = SrgbToLinear(p[c]);
  }
  oiio::ImageSpec config;
  config.tile_width = config.tile_height = 64;
  config.set_format(srgb ? oiio::TypeDesc::HALF : in.spec().format);
  config.attribute("compression", "zip");
  config.attribute("maketx:filtername", "box");
  config.attribute("maketx:compute_average", 1);
  // Unique per process and call: workers sharing the folder each write their own.
  static std::atomic<unsigned> serial{0};
  const std::filesystem::path tmp =
      out.parent_path() / (out.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                           std::to_string(serial++) + ".tx");
  if (!oiio::ImageBufAlgo::make_texture(oiio::ImageBufAlgo::MakeTxTexture, rgba, tmp.string(), config)) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error("cannot prepare " + name + " as " + out.string() + ": " + oiio::geterror());
  }
  std::filesystem::rename(tmp, out);  // throws filesystem_error (a full disk is its kind)
}

}  // namespace

struct TextureSystem::Impl {
  oiio::TextureSystem* ts = nullptr;
  // Unique in the process (an address could be reused by a later system).
  std::uint64_t id = next_id++;

  ~Impl() {
    if (ts) oiio::TextureSystem::destroy(ts);
  }

  // OIIO's state of the calling thread (its micro-cache of tiles), found once per thread
  // and system: get_perthread_info looks it up in thread-specific storage at every call.
  oiio::TextureSystem::Perthread* PerThread() const {
    thread_local struct {
      std::uint64_t id = 0;
      oiio::TextureSystem::Perthread* info = nullptr;
    } cached;
    if (cached.id != id) cached = {id, ts->get_perthread_info()};
    return cached.info;
  }

  static inline std::atomic<std::uint64_t> next_id{1};
};

TextureSystem::TextureSystem(TextureSystemOptions options)
    : options_(std::move(options)), impl_(std::make_unique<Impl>()) {
  impl_->ts = oiio::TextureSystem::create(/*shared=*/false);
  impl_->ts->attribute("max_memory_MB", static_cast<float>(options_.cache_mib));
  // Prepared files are tiled and MIP-mapped; anything else is not ours.
  impl_->ts->attribute("accept_untiled", 0);
  impl_->ts->attribute("automip", 0);
  std::filesystem::create_directories(options_.prepared_dir);
}

TextureSystem::~TextureSystem() = default;

PreparedTexture TextureSystem::Prepare(const std::string& digest, TextureUse use, TextureEncoding encoding,
                                       const SourceFile& source) {
  // Named by what decides its contents (the blob, the use and the encoding asked for) and
  // by the decoding that followed from them and the file: only one of the two can exist.
  static constexpr const char* kUses[] = {"color", "data"};
  static constexpr const char* kEncodings[] = {"byuse", "srgb", "linear"};
  const std::string stem = Hex(digest) + "-" + kPreparedVersion + "-" + kUses[static_cast<int>(use)] + "-" +
                           kEncodings[static_cast<int>(encoding)];
  const auto prepared = [&](bool srgb) { return options_.prepared_dir / (stem + (srgb ? "-srgb.tx" : "-linear.tx")); };
  bool srgb = std::filesystem::exists(prepared(true));
  if (!srgb && !std::filesystem::exists(prepared(false))) {
    const std::filesystem::path file = source();
    srgb = DecodesSrgb(file, digest, use, encoding);
    WritePrepared(file, digest, srgb, prepared(srgb));
  }
  const std::filesystem::path file = prepared(srgb);
  oiio::TextureSystem::TextureHandle* handle = impl_->ts->get_texture_handle(oiio::ustring(file.string()));
  if (!handle || !impl_->ts->good(handle))
    throw std::runtime_error("texture " + digest + ": prepared file " + file.string() +
                             " cannot be opened: " + impl_->ts->geterror());
  return PreparedTexture{handle, srgb};
}

Rgba TextureSystem::Lookup(const PreparedTexture& texture, const TextureLookup& at, TextureWrap wrap) const {
  oiio::TextureOpt opt;
  opt.swrap = opt.twrap = OiioWrap(wrap);
  opt.fill = 1;
  // Bilinear within a level (OIIO's default, bicubic when magnifying, overshoots at edges:
  // a cut-out's alpha or a metallic value would leave [0, 1]).
  opt.interpmode = oiio::TextureOpt::InterpBilinear;
  const bool point = at.axis1.x == 0 && at.axis1.y == 0 && at.axis2.x == 0 && at.axis2.y == 0;
  if (point) {
    opt.mipmode = oiio::TextureOpt::MipModeNoMIP;  // the finest level, without choosing one
  } else if (at.filter == TextureFilter::kIsotropic) {
    opt.mipmode = oiio::TextureOpt::MipModeTrilinear;
  } else {
    opt.mipmode = oiio::TextureOpt::MipModeAniso;
    opt.anisotropic = kMaxAnisotropy;
  }
  float rgba[4] = {1, 0, 1, 1};
  auto* handle = static_cast<oiio::TextureSystem::TextureHandle*>(texture.handle);
  impl_->ts->texture(handle, impl_->PerThread(), opt, at.uv.x, at.uv.y, at.axis1.x, at.axis1.y,
                     at.axis2.x, at.axis2.y, 4, rgba);
  return Rgba{Rgb(rgba[0], rgba[1], rgba[2]), rgba[3]};
}

Rgba TextureSystem::Average(const PreparedTexture& texture) const {
  float rgba[4] = {0, 0, 0, 1};
  auto* handle = static_cast<oiio::TextureSystem::TextureHandle*>(texture.handle);
  // All four channels: the fourth is opacity, an ordinary channel (ToRgba).
  impl_->ts->get_texture_info(handle, impl_->PerThread(), 0, oiio::ustring("averagecolor"),
                              oiio::TypeDesc(oiio::TypeDesc::FLOAT, 4), rgba);
  return Rgba{Rgb(rgba[0], rgba[1], rgba[2]), rgba[3]};
}

std::uint64_t TextureSystem::CacheBytes() const {
  long long bytes = 0;
  impl_->ts->imagecache()->getattribute("stat:cache_memory_used", oiio::TypeDesc::INT64, &bytes);
  return static_cast<std::uint64_t>(bytes);
}

}  // namespace farm
