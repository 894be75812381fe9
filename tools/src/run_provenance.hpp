#pragma once
// Where a report's figures come from: the commit, the machine and the
// build, so that a figure quoted later can be traced and rerun.
#include <string>

namespace tools {

// "2026-12-07 06:30 UTC, commit 3cb0302 (with local changes), Intel(R) ...
// (2 cores), release build". The commit is that of the source tree at
// `source_dir` ("not a git checkout" when git cannot tell).
std::string run_provenance(const std::string& source_dir);

}  // namespace tools
