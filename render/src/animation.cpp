#include "cw4d/render/animation.hpp"

#include <gif_lib.h>
#include <webp/encode.h>
#include <webp/mux.h>

#include <cmath>
#include <cstring>
#include <memory>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"

namespace cw4d::render {

std::string encode_webp_animation(const std::vector<Image8>& frames, const AnimationOptions& o) {
  if (frames.empty()) throw InputError("an animation needs at least one frame");
  const int w = frames.front().width, h = frames.front().height;
  for (const auto& f : frames) {
    if (f.width != w || f.height != h) throw InputError("animation frames differ in size");
    if ((f.channels != 3 && f.channels != 4) ||
        f.bytes.size() != static_cast<std::size_t>(w) * h * f.channels)
      throw InputError("animation frames must be 8-bit RGB or RGBA");
  }
  if (w < 1 || h < 1 || w > WEBP_MAX_DIMENSION || h > WEBP_MAX_DIMENSION)
    throw InputError("WebP frames are 1..16383 pixels a side");
  if (o.frame_ms < 1 || o.frame_ms > 60000)
    throw InputError("the frame time must be 1..60000 ms, not " + std::to_string(o.frame_ms));
  if (!(o.quality >= 0.0f && o.quality <= 100.0f))
    throw InputError("the WebP quality must be 0..100");

  WebPAnimEncoderOptions eo;
  if (!WebPAnimEncoderOptionsInit(&eo)) throw Error("libwebp: version mismatch");
  eo.anim_params.loop_count = o.loop_count;
  std::unique_ptr<WebPAnimEncoder, void (*)(WebPAnimEncoder*)> enc(WebPAnimEncoderNew(w, h, &eo),
                                                                   WebPAnimEncoderDelete);
  if (!enc) throw Error("libwebp: cannot create the animation encoder");
  WebPConfig config;
  if (!WebPConfigInit(&config)) throw Error("libwebp: version mismatch");
  config.lossless = o.lossless ? 1 : 0;
  config.quality = o.quality;
  int timestamp = 0;
  for (const auto& f : frames) {
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
    const int added = WebPAnimEncoderAdd(enc.get(), &pic, timestamp, &config);
    WebPPictureFree(&pic);
    if (!added)
      throw Error(std::string("libwebp: cannot encode a frame: ") +
                  WebPAnimEncoderGetError(enc.get()));
    timestamp += o.frame_ms;
  }
  if (!WebPAnimEncoderAdd(enc.get(), nullptr, timestamp, nullptr))
    throw Error(std::string("libwebp: ") + WebPAnimEncoderGetError(enc.get()));
  WebPData data;
  WebPDataInit(&data);
  if (!WebPAnimEncoderAssemble(enc.get(), &data))
    throw Error(std::string("libwebp: cannot assemble the animation: ") +
                WebPAnimEncoderGetError(enc.get()));
  std::string out(reinterpret_cast<const char*>(data.bytes), data.size);
  WebPDataClear(&data);
  return out;
}

void write_webp_animation(const std::string& path, const std::vector<Image8>& frames,
                          const AnimationOptions& options) {
  write_file_atomically(path, encode_webp_animation(frames, options));
}

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

std::string encode_gif_animation(const std::vector<Image8>& frames, const AnimationOptions& o) {
  if (frames.empty()) throw InputError("an animation needs at least one frame");
  const int w = frames.front().width, h = frames.front().height;
  for (const Image8& f : frames) {
    if (f.width != w || f.height != h) throw InputError("animation frames differ in size");
    if ((f.channels != 3 && f.channels != 4) ||
        f.bytes.size() != static_cast<std::size_t>(f.width) * f.height * f.channels)
      throw InputError("animation frames must be 8-bit RGB or RGBA");
  }
  if (w < 1 || h < 1 || w > 65535 || h > 65535)
    throw InputError("GIF frames are 1..65535 pixels a side");
  if (o.frame_ms < 1 || o.frame_ms > 60000)
    throw InputError("the frame time must be 1..60000 ms, not " + std::to_string(o.frame_ms));
  if (o.loop_count < 0 || o.loop_count > 65535)
    throw InputError("the GIF loop count must be 0..65535");

  std::string out;
  int error = 0;
  GifFileType* gif = EGifOpen(&out, append_gif_bytes, &error);
  if (!gif) gif_failed("cannot start the file", error);
  struct Closer {
    GifFileType*& gif;
    ~Closer() {
      if (gif) EGifCloseFile(gif, nullptr);
    }
  } closer{gif};
  EGifSetGifVersion(gif, true);
  if (EGifPutScreenDesc(gif, w, h, 8, 0, nullptr) == GIF_ERROR)
    gif_failed("screen descriptor", gif->Error);
  // NETSCAPE2.0 application block: how often the animation repeats (0: forever).
  const unsigned char app[] = {'N', 'E', 'T', 'S', 'C', 'A', 'P', 'E', '2', '.', '0'};
  const unsigned char loop[] = {1, static_cast<unsigned char>(o.loop_count & 0xff),
                                static_cast<unsigned char>(o.loop_count >> 8)};
  if (EGifPutExtensionLeader(gif, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
      EGifPutExtensionBlock(gif, sizeof app, app) == GIF_ERROR ||
      EGifPutExtensionBlock(gif, sizeof loop, loop) == GIF_ERROR ||
      EGifPutExtensionTrailer(gif) == GIF_ERROR)
    gif_failed("loop block", gif->Error);

  const std::size_t n = static_cast<std::size_t>(w) * h;
  std::vector<GifByteType> r(n), g(n), b(n), index(n);
  GraphicsControlBlock gcb{};
  gcb.DisposalMode = DISPOSE_DO_NOT;
  gcb.UserInputFlag = false;
  gcb.DelayTime = std::max(1, static_cast<int>(std::lround(o.frame_ms / 10.0)));
  gcb.TransparentColor = NO_TRANSPARENT_COLOR;
  GifByteType gce[4];
  const std::size_t gce_size = EGifGCBToExtension(&gcb, gce);
  for (const Image8& f : frames) {
    for (std::size_t i = 0; i < n; ++i) {
      r[i] = f.bytes[i * f.channels];
      g[i] = f.bytes[i * f.channels + 1];
      b[i] = f.bytes[i * f.channels + 2];
    }
    int colors = 256;
    GifColorType palette[256];
    if (GifQuantizeBuffer(static_cast<unsigned>(w), static_cast<unsigned>(h), &colors, r.data(),
                          g.data(), b.data(), index.data(), palette) == GIF_ERROR)
      throw Error("giflib: cannot reduce a frame to 256 colors");
    std::unique_ptr<ColorMapObject, void (*)(ColorMapObject*)> map(GifMakeMapObject(256, palette),
                                                                   GifFreeMapObject);
    if (!map) throw Error("giflib: out of memory");
    if (EGifPutExtension(gif, GRAPHICS_EXT_FUNC_CODE, static_cast<int>(gce_size), gce) ==
            GIF_ERROR ||
        EGifPutImageDesc(gif, 0, 0, w, h, false, map.get()) == GIF_ERROR)
      gif_failed("frame header", gif->Error);
    for (int y = 0; y < h; ++y)
      if (EGifPutLine(gif, index.data() + static_cast<std::size_t>(y) * w, w) == GIF_ERROR)
        gif_failed("frame pixels", gif->Error);
  }
  GifFileType* done = gif;
  gif = nullptr;
  if (EGifCloseFile(done, &error) == GIF_ERROR) gif_failed("cannot finish the file", error);
  return out;
}

void write_gif_animation(const std::string& path, const std::vector<Image8>& frames,
                         const AnimationOptions& options) {
  write_file_atomically(path, encode_gif_animation(frames, options));
}

}  // namespace cw4d::render
