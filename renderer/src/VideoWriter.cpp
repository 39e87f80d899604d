// Video and image-sequence sinks of a path run.
#include "renderer/VideoWriter.h"

#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "renderer/ImageEncoder.h"
#include "renderer/Renderer.h"

namespace renderer {

namespace {

bool onPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string p(path);
  std::size_t start = 0;
  while (start <= p.size()) {
    std::size_t end = p.find(':', start);
    if (end == std::string::npos) end = p.size();
    const std::string dir = p.substr(start, end - start);
    if (!dir.empty() && ::access((dir + "/" + program).c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

void ignoreSigpipe() {
  static std::once_flag once;
  std::call_once(once, [] { std::signal(SIGPIPE, SIG_IGN); });
}

hlod::Result<std::unique_ptr<VideoWriter>> VideoWriter::open(const std::filesystem::path& path,
                                                             int width, int height, double fps) {
  if (!onPath("ffmpeg"))
    return hlod::makeError("writing " + path.string() +
                           " needs ffmpeg on the PATH (install ffmpeg, or give a folder for a "
                           "PNG sequence)");
  if (width % 2 || height % 2)
    return hlod::makeError("an .mp4 (yuv420p) needs an even frame width and height");
  if (!(fps > 0.0 && fps <= 1000.0)) return hlod::makeError("fps must be in (0, 1000]");
  ignoreSigpipe();
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", fps);
  // Niced and single-threaded: the encoder is background work and must not take the cores the
  // frames are timed on (a free-running libx264 pushes real-time frames over their budget).
  const std::string cmd = "nice -n 19 ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgba -s " +
                          std::to_string(width) + "x" + std::to_string(height) + " -r " + rate +
                          " -i - -c:v libx264 -preset veryfast -threads 1 -pix_fmt yuv420p " +
                          "-movflags +faststart " + shellQuote(path.string());
  std::unique_ptr<VideoWriter> v(new VideoWriter());
  v->pipe_ = ::popen(cmd.c_str(), "w");
  if (!v->pipe_) return hlod::makeError("cannot start ffmpeg: " + std::string(strerror(errno)));
  v->path_ = path;
  v->width_ = width;
  v->height_ = height;
  return v;
}

VideoWriter::~VideoWriter() {
  if (pipe_) ::pclose(pipe_);
}

hlod::Status VideoWriter::write(const hlod::Image& image) {
  if (!pipe_) return hlod::makeError("the video " + path_.string() + " is closed");
  if (image.width != width_ || image.height != height_)
    return hlod::makeError("a frame of another size than the video's");
  if (std::fwrite(image.pixels.data(), 1, image.pixels.size(), pipe_) != image.pixels.size())
    return hlod::makeError("ffmpeg stopped taking frames for " + path_.string());
  return hlod::Ok{};
}

hlod::Status VideoWriter::close() {
  if (!pipe_) return hlod::Ok{};
  const int st = ::pclose(pipe_);
  pipe_ = nullptr;
  if (st != 0) return hlod::makeError("ffmpeg failed writing " + path_.string());
  return hlod::Ok{};
}

hlod::Status VideoSink::onFrame(const hlod::FrameRecord&, const hlod::Image* pixels) {
  if (!pixels) return hlod::makeError("internal: the video sink got no pixels");
  return writer_->write(*pixels);
}

hlod::Status VideoSink::finish() {
  return writer_->close();
}

std::string ImageSequenceSink::frameName(std::uint64_t index, const std::string& extension) {
  char name[48];
  std::snprintf(name, sizeof name, "frame_%05llu.%s", static_cast<unsigned long long>(index),
                extension.c_str());
  return name;
}

hlod::Status ImageSequenceSink::onFrame(const hlod::FrameRecord& record,
                                        const hlod::Image* pixels) {
  if (!pixels) return hlod::makeError("internal: the image sink got no pixels");
  const std::string path = (dir_ / frameName(record.index, extension_)).string();
  auto bytes = extension_ == "jpg" ? encodeJpeg(*pixels, quality_) : encodePng(*pixels);
  if (!bytes) return hlod::makeError(path + ": " + bytes.message());
  return writeBytes(path, *bytes);
}

}  // namespace renderer
