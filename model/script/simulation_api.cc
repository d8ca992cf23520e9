#include "model/script/simulation_api.h"

#include <cmath>
#include <lua.hpp>
#include <numbers>

#include "model/core/error.h"

namespace orcs::script {
namespace {

// The functions below raise Lua errors (longjmp): none holds a C++ object with a destructor when it may raise.

SimulationApi& Api(lua_State* state) {
  return *static_cast<SimulationApi*>(lua_touserdata(state, lua_upvalueindex(1)));
}

std::string_view NameArgument(lua_State* state, int index) {
  std::size_t length = 0;
  const char* text = luaL_checklstring(state, index, &length);
  return {text, length};
}

// A motor given as a handle (orcs.motor: its index in orcs.motors(), from 1) or by name.
const SimulationApi::Motor& MotorArgument(lua_State* state, const char* function) {
  const SimulationApi& api = Api(state);
  if (lua_type(state, 1) == LUA_TNUMBER) {
    const SimulationApi::Motor* motor = api.MotorOfHandle(static_cast<long long>(luaL_checkinteger(state, 1)));
    if (motor == nullptr) {
      luaL_error(state, "orcs.%s: %d is not a motor handle (orcs.motor(name) gives one)", function,
                 static_cast<int>(lua_tointeger(state, 1)));
    }
    return *motor;
  }
  const SimulationApi::Motor* motor = api.FindMotor(NameArgument(state, 1));
  if (motor == nullptr) {
    luaL_error(state, "orcs.%s: agent '%s' has no motor '%s' (orcs.motors() lists them)", function,
               api.agent_name().c_str(), lua_tostring(state, 1));
  }
  return *motor;
}

// A body given as a handle (orcs.body) or by name.
int BodyArgument(lua_State* state, const char* function) {
  const SimulationApi& api = Api(state);
  if (lua_type(state, 1) == LUA_TNUMBER) {
    const int body = api.BodyOfHandle(static_cast<long long>(luaL_checkinteger(state, 1)));
    if (body < 0) luaL_error(state, "orcs.%s: %d is not a body handle (orcs.body(name) gives one)", function, static_cast<int>(lua_tointeger(state, 1)));
    return body;
  }
  const int body = api.FindBody(NameArgument(state, 1));
  if (body < 0) {
    luaL_error(state, "orcs.%s: agent '%s' has no body '%s' (names like \"Middle/Head\")", function,
               api.agent_name().c_str(), lua_tostring(state, 1));
  }
  return body;
}

int PushNumbers(lua_State* state, std::initializer_list<double> numbers) {
  for (double number : numbers) lua_pushnumber(state, number);
  return static_cast<int>(numbers.size());
}

int Time(lua_State* state) {
  lua_pushnumber(state, Api(state).simulation().time());
  return 1;
}

int ValueOf(lua_State* state) {
  const Value* value = Api(state).simulation().repository().Find(NameArgument(state, 1));
  if (value == nullptr) return luaL_error(state, "orcs.value: no value '%s' in the repository", lua_tostring(state, 1));
  switch (value->type()) {
    case ValueType::kBool: lua_pushboolean(state, value->as_bool()); return 1;
    case ValueType::kInt: lua_pushinteger(state, value->as_int()); return 1;
    case ValueType::kDouble: lua_pushnumber(state, value->as_double()); return 1;
    case ValueType::kString: {
      const std::string& text = value->as_string();
      lua_pushlstring(state, text.data(), text.size());
      return 1;
    }
    case ValueType::kColor: {
      const Color color = value->as_color();
      return PushNumbers(state, {double(color.r), double(color.g), double(color.b), double(color.a)});
    }
    case ValueType::kVector3: {
      const Eigen::Vector3d& v = value->as_vector3();
      return PushNumbers(state, {v.x(), v.y(), v.z()});
    }
    case ValueType::kQuaternion: {
      const Eigen::Quaterniond q = value->as_quaternion();
      return PushNumbers(state, {q.w(), q.x(), q.y(), q.z()});
    }
  }
  return 0;
}

int Motors(lua_State* state) {
  const std::vector<std::string>& names = Api(state).motor_names();
  lua_createtable(state, static_cast<int>(names.size()), 0);
  for (std::size_t m = 0; m < names.size(); ++m) {
    lua_pushlstring(state, names[m].data(), names[m].size());
    lua_rawseti(state, -2, static_cast<lua_Integer>(m + 1));
  }
  return 1;
}

int MotorHandle(lua_State* state) {
  const SimulationApi& api = Api(state);
  const std::string_view name = NameArgument(state, 1);
  for (std::size_t m = 0; m < api.motor_names().size(); ++m) {
    if (api.motor_names()[m] == name) {
      lua_pushinteger(state, static_cast<lua_Integer>(m + 1));
      return 1;
    }
  }
  return luaL_error(state, "orcs.motor: agent '%s' has no motor '%s' (orcs.motors() lists them)",
                    api.agent_name().c_str(), lua_tostring(state, 1));
}

int Angle(lua_State* state) {
  lua_pushnumber(state, MotorArgument(state, "angle").angle->as_double());
  return 1;
}

int JointRate(lua_State* state) {
  lua_pushnumber(state, Api(state).simulation().physics().joint_rate(MotorArgument(state, "joint_rate").joint));
  return 1;
}

int MotorTorque(lua_State* state) {
  lua_pushnumber(state, Api(state).simulation().physics().joint_motor_torque(MotorArgument(state, "motor_torque").joint));
  return 1;
}

int Body(lua_State* state) {
  const int handle = Api(state).HandleOf(NameArgument(state, 1));
  if (handle < 0) {
    return luaL_error(state, "orcs.body: agent '%s' has no body '%s' (names like \"Middle/Head\")",
                      Api(state).agent_name().c_str(), lua_tostring(state, 1));
  }
  lua_pushinteger(state, handle);
  return 1;
}

int Position(lua_State* state) {
  const Eigen::Vector3d p = Api(state).simulation().physics().body_state(BodyArgument(state, "position")).position;
  return PushNumbers(state, {p.x(), p.y(), p.z()});
}

int Velocity(lua_State* state) {
  const Eigen::Vector3d v =
      Api(state).simulation().physics().body_state(BodyArgument(state, "velocity")).linear_velocity;
  return PushNumbers(state, {v.x(), v.y(), v.z()});
}

int Orientation(lua_State* state) {
  const Eigen::Quaterniond q =
      Api(state).simulation().physics().body_state(BodyArgument(state, "orientation")).orientation;
  return PushNumbers(state, {q.w(), q.x(), q.y(), q.z()});
}

int Tilt(lua_State* state) {
  const Eigen::Quaterniond q = Api(state).simulation().physics().body_state(BodyArgument(state, "tilt")).orientation;
  const double up = std::clamp((q * Eigen::Vector3d::UnitY()).y(), -1.0, 1.0);
  lua_pushnumber(state, std::acos(up) * 180.0 / std::numbers::pi);
  return 1;
}

int Contact(lua_State* state) {
  const int body = BodyArgument(state, "contact");
  bool touching = false;
  for (const physics::Contact& contact : Api(state).simulation().physics().contacts()) {
    if (!contact.excluded && (contact.body1 == body || contact.body2 == body)) {
      touching = true;
      break;
    }
  }
  lua_pushboolean(state, touching);
  return 1;
}

int Accel(lua_State* state) {
  const SimulationApi& api = Api(state);
  const auto* board = api.FindBoard(NameArgument(state, 1));
  if (board == nullptr) {
    return luaL_error(state, "orcs.accel: agent '%s' has no accelerometer board '%s' (\"ABFR\", ...)",
                      api.agent_name().c_str(), lua_tostring(state, 1));
  }
  return PushNumbers(state, {board->first->as_double(), board->second->as_double()});
}

int Random(lua_State* state) {
  lua_pushnumber(state, ScriptSandbox::Of(state).random().Uniform());
  return 1;
}

// A finite number argument, else an error naming the function.
double FiniteArgument(lua_State* state, int index, const char* function) {
  const double number = luaL_checknumber(state, index);
  if (!std::isfinite(number)) luaL_error(state, "orcs.%s: expected a finite number, found %f", function, number);
  return number;
}

int SetAngle(lua_State* state) {
  const SimulationApi::Motor& motor = MotorArgument(state, "set_angle");
  const double degrees = FiniteArgument(state, 2, "set_angle");
  motor.desired_angle->Set(degrees);
  return 0;
}

int SetTorque(lua_State* state) {
  const SimulationApi::Motor& motor = MotorArgument(state, "set_torque");
  const double torque = FiniteArgument(state, 2, "set_torque");
  if (torque < -1.0 || torque > 1.0) return luaL_error(state, "orcs.set_torque: expected a raw torque −1…1, found %f", torque);
  motor.desired_torque->Set(torque);
  return 0;
}

}  // namespace

SimulationApi::SimulationApi(const scene::Simulation& simulation, int agent, VariableRepository* inputs)
    : simulation_(simulation), inputs_(inputs) {
  const aseries::ASeriesLayout& layout = simulation.model().agents()[agent];
  const aseries::ASeriesMorphology& morphology = simulation.model().morphology(agent);
  agent_name_ = layout.agent_name;
  const std::string prefix = "/Sim/" + agent_name_ + "/";
  for (std::size_t m = 0; m < morphology.motors.size(); ++m) {
    const std::string& name = morphology.motors[m].name;
    Motor motor;
    motor.joint = layout.motors[m];
    motor.angle = &simulation.repository().Get(prefix + name + "/JointAngle");
    if (inputs != nullptr) {
      motor.desired_angle = &inputs->Get(prefix + name + "/DesiredAngle");
      motor.desired_torque = &inputs->Get(prefix + name + "/DesiredTorque");
    }
    motor_names_.push_back(name);
    motors_.emplace(name, motor);
  }
  for (const std::string& name : motor_names_) motor_order_.push_back(&motors_.at(name));
  for (std::size_t b = 0; b < morphology.bodies.size(); ++b) {
    body_handles_.emplace(morphology.bodies[b].name, static_cast<int>(b));
    handle_bodies_.push_back(layout.bodies[b]);
  }
  for (const aseries::MorphologyBoard& board : morphology.boards) {
    const Value* axis1 = simulation.repository().Find(prefix + board.name + "/AccelAxis1");
    const Value* axis2 = simulation.repository().Find(prefix + board.name + "/AccelAxis2");
    if (axis1 != nullptr && axis2 != nullptr) boards_.emplace(board.name, std::pair{axis1, axis2});
  }
}

const SimulationApi::Motor* SimulationApi::FindMotor(std::string_view name) const {
  const auto found = motors_.find(name);
  return found == motors_.end() ? nullptr : &found->second;
}

const SimulationApi::Motor* SimulationApi::MotorOfHandle(long long handle) const {
  return handle >= 1 && handle <= static_cast<long long>(motor_order_.size()) ? motor_order_[handle - 1] : nullptr;
}

int SimulationApi::HandleOf(std::string_view name) const {
  const auto found = body_handles_.find(name);
  return found == body_handles_.end() ? -1 : found->second;
}

int SimulationApi::FindBody(std::string_view name) const {
  const int handle = HandleOf(name);
  return handle < 0 ? -1 : handle_bodies_[handle];
}

int SimulationApi::BodyOfHandle(long long handle) const {
  return handle >= 0 && handle < static_cast<long long>(handle_bodies_.size()) ? handle_bodies_[handle] : -1;
}

const std::pair<const Value*, const Value*>* SimulationApi::FindBoard(std::string_view name) const {
  const auto found = boards_.find(name);
  return found == boards_.end() ? nullptr : &found->second;
}

void SimulationApi::Open(ScriptSandbox& sandbox) {
  lua_State* state = sandbox.state();
  lua_newtable(state);
  const auto add = [&](const char* name, lua_CFunction function) {
    lua_pushlightuserdata(state, this);
    lua_pushcclosure(state, function, 1);
    lua_setfield(state, -2, name);
  };
  add("time", Time);
  add("value", ValueOf);
  add("motors", Motors);
  add("motor", MotorHandle);
  add("angle", Angle);
  add("joint_rate", JointRate);
  add("motor_torque", MotorTorque);
  add("body", Body);
  add("position", Position);
  add("velocity", Velocity);
  add("orientation", Orientation);
  add("tilt", Tilt);
  add("contact", Contact);
  add("accel", Accel);
  add("random", Random);
  if (writable()) {
    add("set_angle", SetAngle);
    add("set_torque", SetTorque);
  }
  lua_setglobal(state, "orcs");
}

}  // namespace orcs::script
