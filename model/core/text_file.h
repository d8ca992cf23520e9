// Reading a whole input file, with the project's error convention. Every file orcs reads from outside
// (scenarios, environments, value files, motion records, genomes, measured runs, settings, suites, recordings)
// comes through ReadTextFile: only regular files are read (a FIFO, a device such as /dev/zero or a directory is
// refused before it is opened for reading, so nothing blocks or grows without end), and each kind of file has a
// documented size bound (docs/formats.md, "Input limits").
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace orcs {

/// The size bound of most input files: scenarios, environments, value files, motion records, genomes, column
/// mappings, evolution settings and checkpoints, regression suites and baselines.
inline constexpr std::uint64_t kMaxInputFileBytes = std::uint64_t{64} << 20;  // 64 MiB
/// The size bound of a measured run (docs/gap_measured_data.md): long logs of many columns.
inline constexpr std::uint64_t kMaxMeasuredRunBytes = std::uint64_t{512} << 20;  // 512 MiB

/// The whole content of `path`, at most `max_bytes`. Throws a one-line InputError naming the file:
/// "path: cannot read the file: no such file", "path: not a regular file (a FIFO)", "path: larger than the 64 MiB limit for <kind>",
/// "path: cannot read the file: <reason>". `kind` names the file in the size message ("an input file",
/// "a measured run", ...).
std::string ReadTextFile(const std::string& path, std::uint64_t max_bytes = kMaxInputFileBytes,
                         std::string_view kind = "an input file");

/// "64 MiB", "512 KiB", "100 bytes": a size bound for messages and documentation.
std::string DescribeByteLimit(std::uint64_t bytes);

}  // namespace orcs
