#include "broker/zap_handler.h"

#include <iterator>
#include <stdexcept>
#include <vector>
#include <zmq_addon.hpp>

namespace orcs::broker {
namespace {

constexpr std::size_t kRequestFrames = 7;  // version, request id, domain, address, identity, mechanism, key
constexpr std::size_t kMaxWarned = 1024;   // bound on the "logged once" set
constexpr int kMaxRequestsPerRound = 256;  // so that a flood of handshakes cannot starve the broker's sockets

const char* RoleOf(const std::string& domain) {
  if (domain == net::kWorkerZapDomain) return "worker";
  if (domain == net::kClientZapDomain) return "client";
  return "unknown";
}

}  // namespace

ZapHandler::ZapHandler(zmq::context_t& context, std::map<std::string, net::AllowedCurveKeys> allowed,
                       std::function<void(const std::string&)> log)
    : socket_(context, zmq::socket_type::rep), allowed_(std::move(allowed)), log_(std::move(log)) {
  socket_.set(zmq::sockopt::linger, 0);
  try {
    socket_.bind(kEndpoint);
  } catch (const zmq::error_t& error) {
    throw std::runtime_error(std::string("cannot bind the ZAP handler to ") + kEndpoint + ": " + error.what());
  }
}

void ZapHandler::AnswerRequests() {
  std::vector<zmq::message_t> request;
  for (int i = 0; i < kMaxRequestsPerRound; ++i) {
    request.clear();
    if (!zmq::recv_multipart(socket_, std::back_inserter(request), zmq::recv_flags::dontwait)) return;
    std::string user_id;
    const std::string status = Decide(request, user_id);
    const std::string request_id = request.size() > 1 ? request[1].to_string() : "";
    std::vector<zmq::const_buffer> reply = {zmq::str_buffer("1.0"), zmq::buffer(request_id), zmq::buffer(status),
                                            zmq::buffer(status == "200" ? std::string_view("OK") : "refused"),
                                            zmq::buffer(user_id), zmq::const_buffer()};
    zmq::send_multipart(socket_, reply);
  }
}

std::string ZapHandler::Decide(const std::vector<zmq::message_t>& request, std::string& user_id) {
  if (request.size() != kRequestFrames || request[0].to_string_view() != "1.0") {
    ++stats_.refused;
    LogRefusal("malformed", "refused a connection: malformed ZAP request");
    return "500";
  }
  const std::string domain = request[2].to_string();
  const std::string address = request[3].to_string();
  const std::string mechanism = request[5].to_string();
  const std::string key = request[6].to_string();
  const std::string role = RoleOf(domain);
  if (mechanism != "CURVE" || key.size() != 32) {
    ++stats_.refused;
    LogRefusal(domain + mechanism, "refused a " + role + " connection from " + address + ": mechanism " + mechanism +
                                       " (the broker speaks CURVE only)");
    return "400";
  }
  auto keys = allowed_.find(domain);
  if (keys != allowed_.end()) {
    auto entry = keys->second.find(key);
    if (entry != keys->second.end()) {
      ++stats_.accepted;
      user_id = net::CurveKeyText(key);  // the peer's identity on each of its messages (User-Id)
      return "200";
    }
  }
  ++stats_.refused;
  std::string line = "refused a " + role + " connection from " + address + ": its CURVE key " +
                     net::CurveKeyText(key) + " is not allowed on the " + role + " socket";
  for (const auto& [other_domain, other_keys] : allowed_) {
    auto other = other_keys.find(key);
    if (other_domain != domain && other != other_keys.end()) line += " (it is a " + std::string(RoleOf(other_domain)) +
                                                                     "'s key: " + other->second + ")";
  }
  LogRefusal(domain + key, line);
  return "400";
}

void ZapHandler::LogRefusal(const std::string& key, const std::string& line) {
  if (warned_.size() >= kMaxWarned) warned_.clear();
  if (!warned_.insert(key).second || !log_) return;
  log_(line + " (logged once per key)");
}

}  // namespace orcs::broker
