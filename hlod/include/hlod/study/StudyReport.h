#pragma once
// The accuracy study's report, in a folder a person opens offline:
//   study.json   settings, reference frames, every run with its frames and summary, answers
//   study.csv    one row per run and studied frame
//   pareto.svg   median PSNR against mean frame time, one curve per selector, the Pareto front
//   flip.svg     mean FLIP against mean frame time
//   path.svg     PSNR over the path, one line per Lakhia budget (and per SSE threshold)
//   db-per-ms.svg  dB of median PSNR bought per extra ms, between consecutive budgets
//   strip-N.png  (written by the runner) frames at several budgets beside the reference, with
//                FLIP heat maps
//   index.html   all of it together, with the answers in sentences
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hlod/Result.h"
#include "hlod/study/Study.h"

namespace hlod::study {

struct StudyReport {
  nlohmann::json settings;  // what the study was run with (store, path, size, budgets ...)
  std::vector<ReferenceFrame> reference;
  std::vector<Run> runs;
  std::vector<std::string> strips;  // file names of the strip images, with their captions
  std::vector<std::string> stripCaptions;
};

std::string studyJson(const StudyReport& report, const Answers& answers);
std::string studyCsv(const StudyReport& report);
std::string paretoSvg(const StudyReport& report, bool flip);
std::string pathSvg(const StudyReport& report);
std::string dbPerMsSvg(const Answers& answers);
std::string studyHtml(const StudyReport& report, const Answers& answers);

// Writes the files above (all but the strips) into dir.
Status writeStudyReport(const std::filesystem::path& dir, const StudyReport& report);

// A grid of images (each scaled to cellWidth x cellHeight with a box filter), row by row; an
// empty Image leaves its cell white.
Image composeGrid(const std::vector<Image>& cells, int columns, int cellWidth, int cellHeight);

}  // namespace hlod::study
