#include "cw4d/render/animation.hpp"

#include <gif_lib.h>
#include <webp/encode.h>
#include <webp/mux.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"

namespace cw4d::render {

namespace {

int append_gif_bytes(GifFileType* gif, const GifByteType* data, int size) {
  static_cast<std::string*>(gif->UserData)
      ->append(reinterpret_cast<const char*>(data), static_cast<std::size_t>(size));
  return size;
}

[[noreturn]] void gif_failed(const char* what, int code) {
  const char* text = GifErrorString(code);
  throw Error(std::string("giflib: ") + what + ": " + (text ? text : "unknown error"));
}

}  // namespace

struct AnimationEncoder::Impl {
  Format format;
  int width, height;
  AnimationOptions options;
  bool finished = false;
  // WebP
  WebPAnimEncoder* webp = nullptr;
  WebPConfig config{};
  int timestamp = 0;
  // GIF: the file so far, the frame's channels and palette indices, its control block.
  std::string gif_bytes;
  GifFileType* gif = nullptr;
  std::vector<GifByteType> r, g, b, index;
  GifByteType gce[4] = {};
  std::size_t gce_size = 0;

  ~Impl() {
    if (webp) WebPAnimEncoderDelete(webp);
    if (gif) EGifCloseFile(gif, nullptr);
  }
};

AnimationEncoder::AnimationEncoder(Format format, int w, int h, const AnimationOptions& o)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.format = format;
  m.width = w;
  m.height = h;
  m.options = o;
  if (o.frame_ms < 1 || o.frame_ms > 60000)
    throw InputError("the frame time must be 1..60000 ms, not " + std::to_string(o.frame_ms));
  if (format == Format::WebP) {
    if (w < 1 || h < 1 || w > WEBP_MAX_DIMENSION || h > WEBP_MAX_DIMENSION)
      throw InputError("WebP frames are 1..16383 pixels a side");
    if (!(o.quality >= 0.0f && o.quality <= 100.0f))
      throw InputError("the WebP quality must be 0..100");
    WebPAnimEncoderOptions eo;
    if (!WebPAnimEncoderOptionsInit(&eo)) throw Error("libwebp: version mismatch");
    eo.anim_params.loop_count = o.loop_count;
    m.webp = WebPAnimEncoderNew(w, h, &eo);
    if (!m.webp) throw Error("libwebp: cannot create the animation encoder");
    if (!WebPConfigInit(&m.config)) throw Error("libwebp: version mismatch");
    m.config.lossless = o.lossless ? 1 : 0;
    m.config.quality = o.quality;
    return;
  }
  if (w < 1 || h < 1 || w > 65535 || h > 65535)
    throw InputError("GIF frames are 1..65535 pixels a side");
  if (o.loop_count < 0 || o.loop_count > 65535)
    throw InputError("the GIF loop count must be 0..65535");
  int error = 0;
  m.gif = EGifOpen(&m.gif_bytes, append_gif_bytes, &error);
  if (!m.gif) gif_failed("cannot start the file", error);
  EGifSetGifVersion(m.gif, true);
  if (EGifPutScreenDesc(m.gif, w, h, 8, 0, nullptr) == GIF_ERROR)
    gif_failed("screen descriptor", m.gif->Error);
  // NETSCAPE2.0 application block: how often the animation repeats (0: forever).
  const unsigned char app[] = {'N', 'E', 'T', 'S', 'C', 'A', 'P', 'E', '2', '.', '0'};
  const unsigned char loop[] = {1, static_cast<unsigned char>(o.loop_count & 0xff),
                                static_cast<unsigned char>(o.loop_count >> 8)};
  if (EGifPutExtensionLeader(m.gif, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
      EGifPutExtensionBlock(m.gif, sizeof app, app) == GIF_ERROR ||
      EGifPutExtensionBlock(m.gif, sizeof loop, loop) == GIF_ERROR ||
      EGifPutExtensionTrailer(m.gif) == GIF_ERROR)
    gif_failed("loop block", m.gif->Error);
  const std::size_t n = static_cast<std::size_t>(w) * h;
  m.r.resize(n);
  m.g.resize(n);
  m.b.resize(n);
  m.index.resize(n);
  GraphicsControlBlock gcb{};
  gcb.DisposalMode = DISPOSE_DO_NOT;
  gcb.UserInputFlag = false;
  gcb.DelayTime = std::max(1, static_cast<int>(std::lround(o.frame_ms / 10.0)));
  gcb.TransparentColor = NO_TRANSPARENT_COLOR;
  m.gce_size = EGifGCBToExtension(&gcb, m.gce);
}

AnimationEncoder::~AnimationEncoder() = default;

void AnimationEncoder::add(const Image8& f) {
  Impl& m = *impl_;
  if (m.finished) throw Error("the animation is finished: no more frames");
  const int w = m.width, h = m.height;
  if (f.width != w || f.height != h) throw InputError("animation frames differ in size");
  if ((f.channels != 3 && f.channels != 4) ||
      f.bytes.size() != static_cast<std::size_t>(w) * h * f.channels)
    throw InputError("animation frames must be 8-bit RGB or RGBA");
  if (m.format == Format::WebP) {
    WebPPicture pic;
    if (!WebPPictureInit(&pic)) throw Error("libwebp: version mismatch");
    pic.width = w;
    pic.height = h;
    pic.use_argb = 1;
    const int ok = f.channels == 4 ? WebPPictureImportRGBA(&pic, f.bytes.data(), 4 * w)
                                   : WebPPictureImportRGB(&pic, f.bytes.data(), 3 * w);
    if (!ok) {
      WebPPictureFree(&pic);
      throw Error("libwebp: cannot import a frame (out of memory)");
    }
    const int added = WebPAnimEncoderAdd(m.webp, &pic, m.timestamp, &m.config);
    WebPPictureFree(&pic);
    if (!added)
      throw Error(std::string("libwebp: cannot encode a frame: ") +
                  WebPAnimEncoderGetError(m.webp));
    m.timestamp += m.options.frame_ms;
  } else {
    const std::size_t n = static_cast<std::size_t>(w) * h;
    for (std::size_t i = 0; i < n; ++i) {
      m.r[i] = f.bytes[i * f.channels];
      m.g[i] = f.bytes[i * f.channels + 1];
      m.b[i] = f.bytes[i * f.channels + 2];
    }
    int colors = 256;
    GifColorType palette[256];
    if (GifQuantizeBuffer(static_cast<unsigned>(w), static_cast<unsigned>(h), &colors, m.r.data(),
                          m.g.data(), m.b.data(), m.index.data(), palette) == GIF_ERROR)
      throw Error("giflib: cannot reduce a frame to 256 colors");
    std::unique_ptr<ColorMapObject, void (*)(ColorMapObject*)> map(GifMakeMapObject(256, palette),
                                                                   GifFreeMapObject);
    if (!map) throw Error("giflib: out of memory");
    if (EGifPutExtension(m.gif, GRAPHICS_EXT_FUNC_CODE, static_cast<int>(m.gce_size), m.gce) ==
            GIF_ERROR ||
        EGifPutImageDesc(m.gif, 0, 0, w, h, false, map.get()) == GIF_ERROR)
      gif_failed("frame header", m.gif->Error);
    for (int y = 0; y < h; ++y)
      if (EGifPutLine(m.gif, m.index.data() + static_cast<std::size_t>(y) * w, w) == GIF_ERROR)
        gif_failed("frame pixels", m.gif->Error);
  }
  ++frames_;
}

std::string AnimationEncoder::finish() {
  Impl& m = *impl_;
  if (m.finished) throw Error("the animation is finished already");
  if (frames_ == 0) throw InputError("an animation needs at least one frame");
  m.finished = true;
  if (m.format == Format::WebP) {
    if (!WebPAnimEncoderAdd(m.webp, nullptr, m.timestamp, nullptr))
      throw Error(std::string("libwebp: ") + WebPAnimEncoderGetError(m.webp));
    WebPData data;
    WebPDataInit(&data);
    if (!WebPAnimEncoderAssemble(m.webp, &data))
      throw Error(std::string("libwebp: cannot assemble the animation: ") +
                  WebPAnimEncoderGetError(m.webp));
    std::string out(reinterpret_cast<const char*>(data.bytes), data.size);
    WebPDataClear(&data);
    return out;
  }
  GifFileType* done = m.gif;
  m.gif = nullptr;
  int error = 0;
  if (EGifCloseFile(done, &error) == GIF_ERROR) gif_failed("cannot finish the file", error);
  return std::move(m.gif_bytes);
}

namespace {

std::string encode_all(AnimationEncoder::Format format, const std::vector<Image8>& frames,
                       const AnimationOptions& o) {
  if (frames.empty()) throw InputError("an animation needs at least one frame");
  // Every frame checked before any is encoded, so that a bad one costs no encoding.
  const Image8& first = frames.front();
  for (const Image8& f : frames) {
    if (f.width != first.width || f.height != first.height)
      throw InputError("animation frames differ in size");
    if ((f.channels != 3 && f.channels != 4) ||
        f.bytes.size() != static_cast<std::size_t>(f.width) * f.height * f.channels)
      throw InputError("animation frames must be 8-bit RGB or RGBA");
  }
  AnimationEncoder encoder(format, first.width, first.height, o);
  for (const Image8& f : frames) encoder.add(f);
  return encoder.finish();
}

}  // namespace

std::string encode_webp_animation(const std::vector<Image8>& frames, const AnimationOptions& o) {
  return encode_all(AnimationEncoder::Format::WebP, frames, o);
}

void write_webp_animation(const std::string& path, const std::vector<Image8>& frames,
                          const AnimationOptions& options) {
  write_file_atomically(path, encode_webp_animation(frames, options));
}

std::string encode_gif_animation(const std::vector<Image8>& frames, const AnimationOptions& o) {
  return encode_all(AnimationEncoder::Format::Gif, frames, o);
}

void write_gif_animation(const std::string& path, const std::vector<Image8>& frames,
                         const AnimationOptions& options) {
  write_file_atomically(path, encode_gif_animation(frames, options));
}

}  // namespace cw4d::render
