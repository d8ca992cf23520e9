#include "worker/osp/agent_interface.h"

namespace orcs::osp {
namespace {

InterfaceValue Bind(scene::Simulation& simulation, const std::string& agent, const std::string& interface_name,
                    const aseries::ValueRange& range) {
  return InterfaceValue{interface_name, &simulation.repository().Get("/Sim/" + agent + interface_name), range};
}

}  // namespace

AgentInterface MakeAgentInterface(scene::Simulation& simulation, int index) {
  aseries::ASeriesAgent& agent = simulation.agent(index);
  AgentInterface interface;
  interface.name = agent.name();
  for (const std::string& motor : agent.motor_names()) {
    interface.inputs.push_back(Bind(simulation, agent.name(), "/" + motor + "/DesiredAngle", aseries::kDesiredAngleRange));
    interface.inputs.push_back(
        Bind(simulation, agent.name(), "/" + motor + "/DesiredTorque", aseries::kDesiredTorqueRange));
  }
  for (const std::string& motor : agent.motor_names()) {
    interface.outputs.push_back(Bind(simulation, agent.name(), "/" + motor + "/JointAngle", aseries::kJointAngleRange));
  }
  for (const aseries::ASeriesBoardLayout& board : agent.layout().boards) {
    for (const char* axis : {"/AccelAxis1", "/AccelAxis2"}) {
      interface.outputs.push_back(Bind(simulation, agent.name(), "/" + board.name + axis, aseries::kAccelAxisRange));
    }
  }
  return interface;
}

}  // namespace orcs::osp
