// Names of the temporary files a write goes through before it is renamed into place (EXR
// and PNG outputs, checkpoints): hidden, beside their target so the rename stays on one file
// system, and carrying the writer's PID so that whoever writes the same target next can
// remove what a killed writer left behind.
#pragma once

#include <filesystem>
#include <string>

namespace prism {

// ".NAME.tmp-PID-N.EXT" for a target NAME.EXT (NAME cut so that the whole stays within
// NAME_MAX, an absurdly long extension dropped), N counting this process's calls.
std::string temporary_name(const std::filesystem::path& target);

// Removes the temporaries of `target` in `dir` whose writer process no longer exists.
void remove_stale_temporaries(const std::filesystem::path& dir,
                              const std::filesystem::path& target);

}  // namespace prism
