#include "model/script/plugin_view.h"

#include <cmath>
#include <stdexcept>

namespace orcs::script {

const SimulationApi::Motor& PluginView::Motor(int motor) const {
  if (motor < 0 || motor >= motor_count()) {
    throw std::out_of_range("plug-in: motor " + std::to_string(motor) + " of " + std::to_string(motor_count()));
  }
  return *api_.FindMotor(api_.motor_names()[motor]);
}

void PluginView::position(int body, double xyz[3]) const {
  const int index = api_.BodyOfHandle(body);
  if (index < 0) throw std::out_of_range("plug-in: body handle " + std::to_string(body));
  const Eigen::Vector3d& p = api_.simulation().physics().body_state(index).position;
  xyz[0] = p.x();
  xyz[1] = p.y();
  xyz[2] = p.z();
}

bool PluginView::contact(int body) const {
  const int index = api_.BodyOfHandle(body);
  if (index < 0) throw std::out_of_range("plug-in: body handle " + std::to_string(body));
  for (const physics::Contact& contact : api_.simulation().physics().contacts()) {
    if (!contact.excluded && (contact.body1 == index || contact.body2 == index)) return true;
  }
  return false;
}

bool PluginView::value(const std::string& path, double& out) const {
  const Value* found = api_.simulation().repository().Find(path);
  if (found == nullptr) return false;
  switch (found->type()) {
    case ValueType::kDouble: out = found->as_double(); return true;
    case ValueType::kInt: out = static_cast<double>(found->as_int()); return true;
    case ValueType::kBool: out = found->as_bool() ? 1.0 : 0.0; return true;
    default: return false;
  }
}

void PluginView::set_angle(int motor, double degrees) {
  if (!api_.writable()) throw std::logic_error("plug-in: a fitness term cannot set motor inputs");
  if (!std::isfinite(degrees)) throw std::invalid_argument("plug-in: set_angle with a non-finite angle");
  Motor(motor).desired_angle->Set(degrees);
}

void PluginView::set_torque(int motor, double torque) {
  if (!api_.writable()) throw std::logic_error("plug-in: a fitness term cannot set motor inputs");
  if (!(torque >= -1.0 && torque <= 1.0)) throw std::invalid_argument("plug-in: set_torque outside −1…1");
  Motor(motor).desired_torque->Set(torque);
}

}  // namespace orcs::script
