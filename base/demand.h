// The always-on invariant check (Drake's DRAKE_DEMAND is the model). orcs has two tiers of checks
// (docs/architecture.md, "Errors and bad input"):
//   - user input — a file, an option, a message, a plug-in's or a script's call — is checked where it enters and
//     refused with orcs::InputError (model/core/error.h): one line naming the file, line or field; the program goes on
//     or exits 2;
//   - an internal invariant — what the code itself guarantees, whatever the input — is checked with ORCS_DEMAND in
//     every build, release included: a false one is a bug in orcs, so the process says where and aborts (a core dump
//     for the report) rather than compute on from a broken state.
// assert() is not used: the default build (RelWithDebInfo) defines NDEBUG, which turned every assert off in the
// binaries users run.
#pragma once

namespace orcs::internal {

/// Prints "orcs: internal invariant failed: CONDITION (MESSAGE) at FILE:LINE in FUNCTION" on stderr and aborts.
[[noreturn]] void DemandFailed(const char* condition, const char* message, const char* file, int line,
                               const char* function) noexcept;

}  // namespace orcs::internal

/// Checks an internal invariant in every build; ORCS_DEMAND_MSG adds why it must hold.
#define ORCS_DEMAND(condition)                                                                   \
  do {                                                                                           \
    if (!(condition)) ::orcs::internal::DemandFailed(#condition, "", __FILE__, __LINE__, __func__); \
  } while (false)
#define ORCS_DEMAND_MSG(condition, message)                                                           \
  do {                                                                                                \
    if (!(condition)) ::orcs::internal::DemandFailed(#condition, message, __FILE__, __LINE__, __func__); \
  } while (false)
/// A place the code never reaches (a switch over every enumerator, a kind refused earlier).
#define ORCS_UNREACHABLE(message) ::orcs::internal::DemandFailed("unreachable", message, __FILE__, __LINE__, __func__)
