// Joining a split path run's segments. See service/SegmentJoin.h.
#include "service/SegmentJoin.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hlod/runtime/Segments.h"

extern char** environ;

namespace service {

namespace fs = std::filesystem;

namespace {

bool isVideo(const fs::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".mp4";
}

fs::path statsJsonOf(const fs::path& part) {
  return isVideo(part) ? part.parent_path() / (part.stem().string() + ".stats.json")
                       : part / "stats.json";
}

hlod::Result<std::string> readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return hlod::makeError("cannot read " + p.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct ReadPart {
  hlod::SegmentPart part;
  nlohmann::json extra;  // the stats file's top level without frames and summary
};

hlod::Result<ReadPart> readPart(const fs::path& part) {
  const fs::path statsPath = statsJsonOf(part);
  auto text = readText(statsPath);
  if (!text)
    return hlod::makeError(part.string() + ": no stats file " + statsPath.string() +
                           " (is it the output of `hlodr render --segment`?)");
  auto frames = hlod::parseStatsFrames(*text);
  if (!frames) return hlod::makeError(statsPath.string() + ": " + frames.message());
  ReadPart r;
  r.extra = nlohmann::json::parse(*text, nullptr, false);
  const auto& seg = r.extra.contains("segment") ? r.extra["segment"] : nlohmann::json();
  auto whole = [&](const char* key) -> long long {
    const auto it = seg.find(key);
    return it != seg.end() && it->is_number_unsigned() ? it->get<long long>() : -1;
  };
  const long long index = whole("index"), count = whole("count"), first = whole("firstFrame"),
                  end = whole("endFrame"), total = whole("runFrames");
  if (!seg.is_object() || index < 0 || count < 1 || first < 0 || end < first || total < end)
    return hlod::makeError(statsPath.string() +
                           ": not a segment's stats (no valid \"segment\" object; render "
                           "the parts with --segment I/N)");
  hlod::SegmentPart& p = r.part;
  p.name = part.string();
  p.spec = {static_cast<std::uint32_t>(index), static_cast<std::uint32_t>(count)};
  p.range = {static_cast<std::uint64_t>(first), static_cast<std::uint64_t>(end)};
  p.runFrames = static_cast<std::uint64_t>(total);
  const auto& session = r.extra.value("session", nlohmann::json::object());
  p.width = session.is_object() ? session.value("width", 0) : 0;
  p.height = session.is_object() ? session.value("height", 0) : 0;
  p.fps = r.extra.value("fps", 0.0);
  p.frames = std::move(*frames);
  r.extra.erase("frames");
  r.extra.erase("summary");
  r.extra.erase("segment");
  return r;
}

// ffmpeg with these arguments, no shell between (paths may hold any character).
hlod::Status runFfmpeg(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>("ffmpeg"));
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (int e = posix_spawnp(&pid, "ffmpeg", nullptr, nullptr, argv.data(), environ); e != 0)
    return hlod::makeError("cannot start ffmpeg (" + std::string(std::strerror(e)) +
                           "): joining .mp4 parts needs ffmpeg on the PATH");
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return hlod::makeError("waiting for ffmpeg failed");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return hlod::makeError("ffmpeg failed joining the parts");
  return hlod::Ok{};
}

// The concat demuxer's list: one `file '...'` line per part, a quote written as '\''.
std::string concatList(const std::vector<fs::path>& files) {
  std::string out;
  for (const fs::path& f : files) {
    out += "file '";
    for (char c : fs::absolute(f).string())
      out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    out += "'\n";
  }
  return out;
}

}  // namespace

hlod::Status concatVideos(const std::vector<fs::path>& parts, const fs::path& output) {
  fs::path dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  const fs::path listFile = dir / (output.stem().string() + ".concat.txt");
  {
    std::ofstream l(listFile, std::ios::binary | std::ios::trunc);
    l << concatList(parts);
    if (!l) return hlod::makeError("cannot write " + listFile.string());
  }
  // Stream copy: the parts were encoded alike (same size, rate and encoder settings).
  auto s = runFfmpeg({"-nostdin", "-loglevel", "error", "-y", "-f", "concat", "-safe", "0", "-i",
                      listFile.string(), "-c", "copy", output.string()});
  std::error_code ec;
  fs::remove(listFile, ec);
  return s;
}

hlod::Result<JoinResult> joinSegments(const std::vector<fs::path>& parts, const fs::path& output) {
  if (parts.empty()) return hlod::makeError("no parts given");
  const bool video = isVideo(output);
  for (const fs::path& p : parts) {
    if (isVideo(p) != video)
      return hlod::makeError(video ? p.string() + " is not an .mp4: join .mp4 parts into an .mp4"
                                   : p.string() +
                                         " is an .mp4: join folders into a folder, "
                                         ".mp4 parts into an .mp4");
    std::error_code ec;
    if (!fs::exists(p, ec)) return hlod::makeError(p.string() + ": no such part");
  }
  std::vector<ReadPart> read;
  std::vector<hlod::SegmentPart> list;
  for (const fs::path& p : parts) {
    auto r = readPart(p);
    if (!r) return r.error();
    read.push_back(std::move(*r));
  }
  for (auto& r : read) list.push_back(r.part);  // a copy: segmentOrder reads, read[] keeps
  auto order = hlod::segmentOrder(list);
  if (!order) return order.error();

  std::vector<hlod::FrameRecord> frames;
  for (std::size_t k : *order)
    frames.insert(frames.end(), read[k].part.frames.begin(), read[k].part.frames.end());
  JoinResult result;
  result.frames = frames.size();
  result.segments = static_cast<std::uint32_t>(parts.size());
  result.summary = hlod::summarize(frames);

  std::error_code ec;
  fs::path statsDir;
  std::string prefix;
  if (video) {
    statsDir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
    prefix = output.stem().string() + ".";
    fs::create_directories(statsDir, ec);
    std::vector<fs::path> files;
    for (std::size_t k : *order) files.push_back(parts[k]);
    auto s = concatVideos(files, output);
    if (!s) return s.error();
  } else {
    statsDir = output;
    fs::create_directories(output, ec);
    if (!fs::is_directory(output))
      return hlod::makeError("cannot create the folder " + output.string());
    // The parts' frames are named by their frame number in the whole run already.
    for (std::size_t k : *order) {
      for (const auto& e : fs::directory_iterator(parts[k], ec)) {
        const std::string n = e.path().filename().string();
        if (n.rfind("frame_", 0) != 0) continue;
        fs::copy_file(e.path(), output / n, fs::copy_options::overwrite_existing, ec);
        if (ec) return hlod::makeError("cannot copy " + e.path().string() + ": " + ec.message());
      }
    }
  }
  nlohmann::json extra = read[(*order)[0]].extra;
  extra["segments"] = result.segments;
  result.statsJson = statsDir / (prefix + "stats.json");
  result.statsCsv = statsDir / (prefix + "stats.csv");
  if (auto s =
          hlod::writeStatsJson(result.statsJson.string(), frames, result.summary, extra.dump());
      !s)
    return s.error();
  if (auto s = hlod::writeStatsCsv(result.statsCsv.string(), frames); !s) return s.error();
  return result;
}

}  // namespace service
