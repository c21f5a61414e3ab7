// The plan file of `scanfill plan` (DESIGN section 10): a TransferPlan and what output.ply's colours need, so that
// `scanfill apply` writes tiles whose points are output.ply's own.
//
// Binary, little-endian: a 32-byte header (the magic "SCNFPLAN", the format version as uint32, 4 zero bytes, the
// payload's length and its FNV-1a 64-bit hash, as uint64), then the payload: the fields of PlanFile in a fixed order,
// each array preceded by its length. A file with another magic, another version, a length that disagrees with the
// file's, a hash that does not match or an inconsistent plan is refused whole with one line naming the file.
#pragma once

#include <cstdint>
#include <filesystem>

#include "nodes/transfer/transfer.h"

namespace scanfill {

// Bumped whenever the payload's layout or meaning changes: plans of other versions are refused, never guessed at.
// 2: the exemplar's colours and intensity, and output.ply's RGB as one of three.
inline constexpr std::uint32_t kPlanFormatVersion = 2;

// output.ply's RGB as the planning run resolved output.colour: by origin, by transform label, or the scan's (or
// exemplar's) own colours carried with its points (the plan then has colours).
enum class PlanColour : std::uint8_t { kOrigin, kLabel, kScan };

struct PlanFile {
  TransferPlan plan;
  int self_label = 0;                       // the analogy's self-reference label (output.ply colours it grey)
  PlanColour colour = PlanColour::kOrigin;  // output.ply's RGB
};

// Writes atomically (temp file + rename). Throws IoError naming the file.
void write_plan(const std::filesystem::path& path, const PlanFile& plan);

// Throws IoError naming the file when it cannot be read or is not a whole, consistent plan of kPlanFormatVersion.
PlanFile read_plan(const std::filesystem::path& path);

}  // namespace scanfill
