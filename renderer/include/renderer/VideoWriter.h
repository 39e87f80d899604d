#pragma once
// An MP4 (H.264, yuv420p) written by an ffmpeg child process from raw RGBA frames on a pipe,
// and the path-run sinks that write frames: the video, or an image sequence.
//
// A process that writes to a pipe whose reader died gets SIGPIPE; hlodr ignores SIGPIPE once at
// start-up (ignoreSigpipe(), also called here), so a dead encoder makes the write fail with an
// Error instead of killing the process. Nothing is changed back: no two sessions fight over it.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/runtime/PathRun.h"

namespace renderer {

// SIGPIPE ignored for the whole process, once (std::call_once).
void ignoreSigpipe();

class VideoWriter {
 public:
  // Starts ffmpeg writing `path`. Needs ffmpeg on the PATH and an even width and height.
  static hlod::Result<std::unique_ptr<VideoWriter>> open(const std::filesystem::path& path,
                                                         int width, int height, double fps);
  ~VideoWriter();  // an unclosed writer closes the pipe (the file may be incomplete)
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  hlod::Status write(const hlod::Image& image);
  // Ends the stream and waits for ffmpeg: an Error when it failed.
  hlod::Status close();

 private:
  VideoWriter() = default;
  std::FILE* pipe_ = nullptr;
  std::filesystem::path path_;
  int width_ = 0, height_ = 0;
};

// Frames into an MP4.
class VideoSink final : public hlod::FrameSink {
 public:
  explicit VideoSink(std::unique_ptr<VideoWriter> writer) : writer_(std::move(writer)) {}
  bool wantsPixels() const override { return true; }
  hlod::Status onFrame(const hlod::FrameRecord& record, const hlod::Image* pixels) override;
  hlod::Status finish() override;

 private:
  std::unique_ptr<VideoWriter> writer_;
};

// Frames as files `dir/frame_00000.EXT` (png or jpg; quality for jpg).
class ImageSequenceSink final : public hlod::FrameSink {
 public:
  ImageSequenceSink(std::filesystem::path dir, std::string extension = "png", int quality = 90)
      : dir_(std::move(dir)), extension_(std::move(extension)), quality_(quality) {}
  bool wantsPixels() const override { return true; }
  hlod::Status onFrame(const hlod::FrameRecord& record, const hlod::Image* pixels) override;
  hlod::Status finish() override { return hlod::Ok{}; }
  static std::string frameName(std::uint64_t index, const std::string& extension);

 private:
  std::filesystem::path dir_;
  std::string extension_;
  int quality_;
};

}  // namespace renderer
