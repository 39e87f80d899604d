// `hlodr concat PART_0 ... PART_N-1 -o OUT`: the segments of a split path run joined into what
// the unsplit run writes (service/SegmentJoin.h).
#include <cstdio>

#include "cmd/Commands.h"
#include "service/SegmentJoin.h"

namespace service::cmd {

const char* const kConcatUsage =
    "usage: hlodr concat PART... -o OUT\n"
    "\n"
    "Joins the outputs of `hlodr render STORE --path PATH.json --segment I/N -o PART` into one\n"
    "run: .mp4 parts into an .mp4 (ffmpeg's concat demuxer, no re-encode), folders of PNGs into\n"
    "a folder, and their stats into one stats.json / stats.csv (frames numbered on, one summary\n"
    "over all of them). The parts may come in any order; a missing segment, a gap or overlap of\n"
    "frames, or parts of different frame sizes or rates are refused before anything is written.\n"
    "\n"
    "options:\n"
    "  -o, --output OUT        the joined .mp4 or folder (required)\n";

int runConcat(const Argv& argv) {
  auto args = Args::parse(argv, {}, {"output"});
  if (!args) return usageError("concat", args.message());
  if (args->positionals().empty() || !args->has("output")) {
    std::fprintf(stderr, "hlodr concat: give the parts and -o OUT\n\n%s", kConcatUsage);
    return 2;
  }
  std::vector<std::filesystem::path> parts(args->positionals().begin(), args->positionals().end());
  const std::string out = args->get("output", "");
  auto joined = joinSegments(parts, out);
  if (!joined) return commandError("concat", joined.message());
  std::printf("%llu frames of %u segments -> %s\nstats: %s\n",
              static_cast<unsigned long long>(joined->frames), joined->segments, out.c_str(),
              joined->statsJson.string().c_str());
  return 0;
}

}  // namespace service::cmd
