#pragma once
// The calibrated c_tex of eq. 1 (Lakhia III-B), written by `hlodr calibrate` and read by
// `hlodr build`. The file is JSON {"cTex": X} at $HLODR_CALIBRATION when set, else
// $XDG_CONFIG_HOME/hlodr/calibration.json, else ~/.config/hlodr/calibration.json.
#include <filesystem>
#include <optional>

#include "hlod/Result.h"

namespace hlod {

// Where the calibration file lives (see above); an Error when no location can be derived.
Result<std::filesystem::path> calibrationPath();

// The stored c_tex, in [0, 1]; nothing when there is no calibration file (or no place for
// one). An Error naming the file when it exists but cannot be read or is malformed: a
// calibration that is silently ignored would build with another c_tex than the user expects.
Result<std::optional<double>> readCalibratedCTex();

// Writes {"cTex": cTex}, creating the folder. cTex must be in [0, 1].
Status writeCalibration(double cTex);

}  // namespace hlod
