#include "model/scene/agent_posing.h"

#include "base/demand.h"

#include <Eigen/Geometry>
#include <cstddef>
#include <deque>

namespace orcs::scene {
namespace {

// Tree nodes are the physics bodies plus the static world, numbered body_count.
struct Edge {
  int joint = -1;  // physics joint index
  int other = -1;  // the node at the edge's other end
};

struct AgentGraph {
  int world = -1;                       // node number of the static world
  std::vector<std::vector<Edge>> edges;  // per node
};

int NodeOf(int body, int world) { return body < 0 ? world : body; }

// The joints between the agent's bodies, and between an agent body and the static world.
AgentGraph GraphOf(const physics::PhysicsModel& physics, const aseries::ASeriesLayout& layout) {
  AgentGraph graph;
  graph.world = physics.body_count();
  graph.edges.resize(static_cast<std::size_t>(physics.body_count()) + 1);
  std::vector<bool> in_agent(static_cast<std::size_t>(physics.body_count()), false);
  for (int body : layout.bodies) in_agent[body] = true;
  for (int joint = 0; joint < physics.joint_count(); ++joint) {
    const int body1 = physics.joint_body1(joint);
    const int body2 = physics.joint_body2(joint);
    if (!in_agent[body1] || (body2 >= 0 && !in_agent[body2])) continue;
    const int node1 = NodeOf(body1, graph.world);
    const int node2 = NodeOf(body2, graph.world);
    graph.edges[node1].push_back({joint, node2});
    graph.edges[node2].push_back({joint, node1});
  }
  return graph;
}

// Every body in the subtree of `node`, `node` included.
std::vector<int> Subtree(int node, const std::vector<std::vector<int>>& children, [[maybe_unused]] int world) {
  std::vector<int> bodies{node};
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    for (int child : children[bodies[i]]) bodies.push_back(child);
  }
  for ([[maybe_unused]] int body : bodies) ORCS_DEMAND_MSG(body != world, "the static world never turns: root it there");
  return bodies;
}

}  // namespace

int PosingRoot(const physics::PhysicsModel& physics, const aseries::ASeriesLayout& layout,
               const aseries::ASeriesMorphology& morphology) {
  const AgentGraph graph = GraphOf(physics, layout);
  if (!graph.edges[graph.world].empty()) return -1;
  const int root = morphology.FindBody(morphology.root_body);
  ORCS_DEMAND_MSG(root >= 0, "the morphology's root body is one of its bodies");
  return layout.bodies[root];
}

std::vector<PosingJoint> PosingOrder(const physics::PhysicsModel& physics, const aseries::ASeriesLayout& layout,
                                     int root) {
  const AgentGraph graph = GraphOf(physics, layout);
  const int root_node = NodeOf(root, graph.world);
  const std::size_t nodes = graph.edges.size();
  std::vector<bool> reached(nodes, false);
  std::vector<int> arrived_by(nodes, -1);  // the joint through which the search reached each node
  std::vector<std::vector<int>> children(nodes);
  std::vector<Edge> hinges;  // (joint, the node it leads to), breadth-first
  std::vector<int> parents;  // the node each of them comes from
  std::deque<int> queue{root_node};
  reached[root_node] = true;
  while (!queue.empty()) {
    const int node = queue.front();
    queue.pop_front();
    for (const Edge& edge : graph.edges[node]) {
      if (edge.joint == arrived_by[node]) continue;  // the way back to the parent
      ORCS_DEMAND_MSG(!reached[edge.other], "the agent's joints form a tree");
      if (reached[edge.other]) continue;
      reached[edge.other] = true;
      arrived_by[edge.other] = edge.joint;
      children[node].push_back(edge.other);
      queue.push_back(edge.other);
      if (physics.joint(edge.joint).motorised) {
        hinges.push_back(edge);
        parents.push_back(node);
      }
    }
  }
  std::vector<int> motor_of(static_cast<std::size_t>(physics.joint_count()), -1);
  for (std::size_t m = 0; m < layout.motors.size(); ++m) motor_of[layout.motors[m]] = static_cast<int>(m);
  std::vector<PosingJoint> order;
  for (std::size_t i = 0; i < hinges.size(); ++i) {
    PosingJoint hinge;
    hinge.joint = hinges[i].joint;
    hinge.motor = motor_of[hinge.joint];
    hinge.proximal_body = parents[i] == graph.world ? -1 : parents[i];
    hinge.distal_bodies = Subtree(hinges[i].other, children, graph.world);
    hinge.sign = physics.joint_body1(hinge.joint) == hinges[i].other ? 1.0 : -1.0;
    ORCS_DEMAND_MSG(hinge.motor >= 0, "every motorised hinge of the agent is one of its motors");
    order.push_back(std::move(hinge));
  }
  ORCS_DEMAND_MSG(order.size() == layout.motors.size(), "every motor is reached from the root");
  return order;
}

HingeLine HingeLineNow(const physics::PhysicsModel& physics, const PosingJoint& hinge,
                       const physics::BodyState& proximal) {
  const physics::JointDescription& joint = physics.joint(hinge.joint);
  if (hinge.proximal_body < 0) return {joint.anchor, joint.axis};
  const physics::BodyDescription& initial = physics.body(hinge.proximal_body);
  // The proximal body's motion since its initial pose: x ↦ p + R·R0⁻¹·(x − p0).
  const Eigen::Quaterniond turn = proximal.orientation * initial.orientation.normalized().conjugate();
  return {proximal.position + turn * (joint.anchor - initial.position), (turn * joint.axis).normalized()};
}

}  // namespace orcs::scene
