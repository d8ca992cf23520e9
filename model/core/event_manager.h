// Named events with observers, and the list of events that occurred in the current step.
//
// Events are strings such as "/Simulation/Step" or "/Sim/SecondSphere/Collision". One manager belongs to one
// simulation state. An event triggered several times in one step is listed once.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace orcs {

class EventManager {
 public:
  using Observer = std::function<void(int event_id)>;

  /// Registers an event (idempotent) and returns its id (0, 1, 2, ... in registration order).
  int Register(std::string_view name);
  /// Id of an event, or -1.
  int Find(std::string_view name) const;
  const std::string& name(int id) const { return events_[id].name; }
  int size() const { return static_cast<int>(events_.size()); }

  /// Calls `observer` every time the event is triggered.
  void AddObserver(int id, Observer observer);

  /// Marks the event as occurred in this step and tells its observers.
  void Trigger(int id);

  /// Starts a new step: the occurred list becomes empty.
  void BeginStep();
  /// Ids of the events triggered since the last BeginStep(), in the order of their first trigger.
  const std::vector<int>& occurred() const { return occurred_; }
  bool occurred(int id) const { return events_[id].occurred; }

 private:
  struct Event {
    std::string name;
    bool occurred = false;
    std::vector<Observer> observers;
  };
  std::vector<Event> events_;
  std::unordered_map<std::string, int> ids_;
  std::vector<int> occurred_;
};

}  // namespace orcs
