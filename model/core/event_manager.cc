#include "model/core/event_manager.h"

namespace orcs {

int EventManager::Register(std::string_view name) {
  if (const int existing = Find(name); existing >= 0) return existing;
  const int id = size();
  events_.push_back({std::string(name), false, {}});
  ids_.emplace(std::string(name), id);
  occurred_.reserve(events_.size());  // so Trigger() never allocates inside a step
  return id;
}

int EventManager::Find(std::string_view name) const {
  const auto it = ids_.find(std::string(name));
  return it == ids_.end() ? -1 : it->second;
}

void EventManager::AddObserver(int id, Observer observer) { events_[id].observers.push_back(std::move(observer)); }

void EventManager::Trigger(int id) {
  Event& event = events_[id];
  if (!event.occurred) {
    event.occurred = true;
    occurred_.push_back(id);
  }
  for (const Observer& observer : event.observers) observer(id);
}

void EventManager::BeginStep() {
  for (int id : occurred_) events_[id].occurred = false;
  occurred_.clear();
}

}  // namespace orcs
