// OSP 1.1 command codes (docs/spec/osp.md, docs/osp.md): the first byte of every datagram.
#pragma once

#include <cstdint>

namespace orcs::osp {

enum Command : std::uint8_t {
  kInit = 5,                 ///< client → server port: byte major, byte minor
  kInitAck = 6,              ///< from the client's own handler socket: byte 1, byte 1
  kEnd = 7,                  ///< ends the session
  kEndAck = 8,
  kResetCommunication = 10,  ///< drops every client
  kResetCommunicationAck = 11,
  kEventId = 20,             ///< string event name
  kEventIdReply = 21,        ///< int eventId (0 = unknown)
  kObserveEvent = 30,        ///< int eventId
  kObserveEventReply = 31,   ///< int eventId
  kValueIds = 40,            ///< string regular expression over repository paths
  kValueIdsCount = 41,       ///< int n
  kValueIdAck = 42,
  kValueIdEntry = 43,        ///< int index, int valueId, string name, string path
  kGetValue = 50,            ///< int valueId
  kGetValueReply = 51,       ///< int valueId (−1 = unknown), string value
  kSetValue = 52,            ///< int valueId, string value
  kSetValueReply = 53,       ///< int valueId, byte status (1 set, 0 parse error, 2 unknown id)
  kObserveValues = 54,       ///< int n, n × int valueId
  kObserveValuesReply = 55,  ///< int n, n × int (the id, or 0 where unknown)
  kStopObservingValues = 56,
  kStopObservingValuesReply = 57,
  kResetSimulation = 70,     ///< int seed
  kResetSimulationAck = 71,  ///< at once (and to everyone after a communication reset)
  kResetDone = 75,           ///< the simulation has reset
  kResetDoneAck = 76,
  kStep = 80,                ///< int agentId, int nIn, nIn × float (normalised)
  kStepAck = 81,             ///< int agentId
  kStepResult = 85,          ///< int agentId, int nOut, int nInfo, int nEvents, int 0, floats, info, event ids
  kStepResultAck = 86,
  kAgentOverview = 90,
  kAgentCount = 91,          ///< int n
  kAgentEntry = 92,          ///< int index, int agentId, string type, byte available, string name
  kAgentEntryAck = 93,
  kAgentInfo = 95,           ///< int agentId
  kAgentInfoReply = 96,      ///< int agentId, int nIn, int nOut, int nInfo, string name
  kAgentValueAck = 97,
  kAgentValue = 98,          ///< int runningIndex, float normMin, float normMax, string valueName
  kTakeControl = 100,        ///< int agentId
  kTakeControlReply = 101,   ///< int agentId, byte ok
  kReleaseControl = 105,     ///< int agentId
  kReleaseControlReply = 106,  ///< int agentId, byte status (1 released, 0 failed, 2 not controlled by you)
};

/// The protocol version a client must ask for in kInit.
constexpr std::uint8_t kMajorVersion = 1;
constexpr std::uint8_t kMinorVersion = 1;

}  // namespace orcs::osp
