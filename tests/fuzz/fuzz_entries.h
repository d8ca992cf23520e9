// One entry function per kind of input orcs parses from outside (docs/architecture.md, "Errors and bad input"). The libFuzzer
// targets (tests/fuzz/*_fuzz.cc) and the regression test (fuzz_regression_test.cc) call the same functions, so a
// crash the fuzzer found stays fixed in the ordinary build.
//
// Contract of every entry: it returns for any bytes. The errors the input's reader documents (InputError for
// files and messages, PhysicsError for a world the engine refuses, MalformedDatagram for datagrams) are caught and
// returned as the text of the rejection; anything else — another exception type, a crash, a sanitizer report,
// a broken round trip (which aborts) — is a bug the fuzzer reports.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace orcs::fuzz {

/// What an entry made of its input.
struct FeedResult {
  bool accepted = true;  ///< the input was read without a documented error (a valid input)
  std::string error;     ///< the documented error's message when not accepted (must be one line)
};

/// An ORCS XML environment: read (EnvironmentReader::ReadString), compiled into a world and stepped twice.
FeedResult FeedEnvironmentXml(std::string_view data);

/// A value file (.val): written to a temporary file, read (ValueFile::Read) and applied to an A-Series world's
/// repository, whose run-time parameters are then checked (Simulation::StepDuration).
FeedResult FeedValueFile(std::string_view data);

/// A keyframe record (motion CSV) for the A-Series (21 motors) and for the pendulum rig (1 motor): parsed, played
/// into an A-Series world's inputs, and written back (FormatKeyframeRecord), which must read back to the same rows.
FeedResult FeedMotionRecord(std::string_view data);

/// A resolved scenario (JSON): parsed (ParseScenario) and checked as a client checks a job before submitting it
/// (evaluation::CheckRequest: world, values, parameter sets, controller, fitness) with an empty genome.
FeedResult FeedScenarioJson(std::string_view data);

/// One broker frame for the receiver its first byte names (mod 4): 0 the broker's worker port (WorkerToBroker),
/// 1 its client port (ClientToBroker), 2 a worker (BrokerToWorker), 3 a client (BrokerToClient); parsed with the
/// receivers' check (proto::ParseEnvelope). A JOB is translated as orcs-worker does (RequestOf + CheckRequest); a
/// RESULT is converted to the results.jsonl object the client writes.
FeedResult FeedBrokerMessage(std::string_view data);

/// OSP 1.1 datagrams (split as SplitDatagrams says, each prefixed by one byte naming the receiving socket: 0 the
/// server port, k client k's handler socket) delivered to an OspServer on an A-Series world, after one INIT.
FeedResult FeedOspDatagrams(std::string_view data);

/// ODCP 1.0 datagrams (split as SplitDatagrams says) answered by an OdcpServer that records into a
/// KeyframeSniffer; the record it made must read back as a keyframe record.
FeedResult FeedOdcpDatagrams(std::string_view data);

/// A measured run for orcs-gap: the native orcs-sim log, or — when the input holds a line "---" — a column mapping
/// (JSON) above it and a mapped CSV below; parsed and its commands turned into a keyframe record.
FeedResult FeedMeasuredRun(std::string_view data);

/// HTTP requests to orcs-view (viewer/view_server.h): the first byte names the server (even: files mode over a
/// recording and a batch folder; odd: live mode with a render sink), the rest is one connection's bytes, answered by
/// ViewServer::Answer — the server's own request parsing, routes and handlers. The text "@token@" in the bytes
/// stands for the live session's control token, so the controlled routes are reached. Every request must get a
/// well-formed answer: status 2xx or 4xx, a 4xx with a one-line error, never a byte of the file kept beside the
/// opened folders (a symlink in the live files folder points at it). Accepted when every answer is 2xx; otherwise
/// the error is the first 4xx answer's status and error line.
FeedResult FeedViewRequest(std::string_view data);

/// Splits fuzz bytes into datagrams: each is a 2-byte little-endian length followed by that many bytes (fewer at
/// the end). The length is not capped below 65535, so over-long datagrams reach the servers too.
std::vector<std::string> SplitDatagrams(std::string_view data);

/// The inverse of SplitDatagrams, for seeds.
std::string JoinDatagrams(const std::vector<std::string>& datagrams);

/// A fuzz target: its name (tests/fuzz/<name>_fuzz.cc) and its entry.
struct FuzzTarget {
  const char* name;                        ///< e.g. "environment_xml"
  FeedResult (*feed)(std::string_view);    ///< its entry function
};

/// Every target, in the order scripts/fuzz.sh runs them.
const std::vector<FuzzTarget>& FuzzTargets();

}  // namespace orcs::fuzz
