#include "cw4d/render/animation.hpp"

#include <webp/encode.h>
#include <webp/mux.h>

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

}  // namespace cw4d::render
