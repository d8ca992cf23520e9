#include "viewer/view_server.h"

#include <arpa/inet.h>
#include <httplib.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"

namespace orcs::viewer {
namespace {

using httplib::Request;
using httplib::Response;

constexpr std::size_t kMaxBodyBytes = 1 << 20;      // POST bodies
constexpr std::size_t kMaxPatternLength = 1000;     // RE2 patterns from the page
constexpr std::size_t kMaxChannelsPerRequest = 4096;
constexpr std::size_t kMaxChannelValues = std::size_t{1} << 22;  // floats per /channels answer: 16 MiB
constexpr std::size_t kMaxValueRows = 5000;
// Connections. Each connection holds one thread while it sends a request, so a client that trickles its request a
// byte at a time holds one for as long as it trickles (cpp-httplib 0.11 times out each read, not a whole
// request): the pool is large enough that a few dozen such connections leave threads for everyone else, a silent
// connection is dropped after kReadTimeout (inside a request) or kKeepAliveTimeout (between requests), and a
// client that does not read its answer after kWriteTimeout. docs/security.md says what is left.
constexpr int kServerThreads = 64;                  // long polls hold a thread for up to 0.5 s each
constexpr int kReadTimeoutSeconds = 2;
constexpr int kKeepAliveTimeoutSeconds = 2;
constexpr int kWriteTimeoutSeconds = 5;

// Strings from a request (a query parameter is any bytes) reach answers, error messages included: bytes that are
// not UTF-8 are replaced (U+FFFD) instead of making dump() throw — which, from the exception handler, ended the
// server with std::terminate.
void SendJson(Response& response, const nlohmann::json& body, int status = 200) {
  response.status = status;
  response.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "application/json");
}

void SendError(Response& response, int status, const std::string& message) {
  SendJson(response, {{"error", message}}, status);
}

template <typename T>
void SendArray(Response& response, const std::vector<T>& data) {
  response.set_content(std::string(reinterpret_cast<const char*>(data.data()), data.size() * sizeof(T)),
                       "application/octet-stream");
}

// The request's body as a JSON object; nullopt (and a 400 sent) when it is not one.
std::optional<nlohmann::json> BodyObject(const Request& request, Response& response) {
  try {
    nlohmann::json body = ParseJson(request.body, "request body");
    if (body.is_object()) return body;
  } catch (const InputError&) {
  }
  SendError(response, 400, "expected a JSON object as the request body");
  return std::nullopt;
}

std::string StringField(const nlohmann::json& body, const char* key) {
  const auto it = body.find(key);
  return it != body.end() && it->is_string() ? it->get<std::string>() : "";
}

// An optional true/false field: `fallback` when absent, an InputError (400) naming the field for anything else.
bool BoolField(const nlohmann::json& body, const char* key, bool fallback) {
  const auto it = body.find(key);
  if (it == body.end()) return fallback;
  if (!it->is_boolean()) throw InputError(key, 0, "expected true or false, found " + it->dump().substr(0, 40));
  return it->get<bool>();
}

// An optional whole number from `min` to `max`: `fallback` when absent, an InputError (400) naming the field else.
int IntField(const nlohmann::json& body, const char* key, int fallback, int min, int max) {
  const auto it = body.find(key);
  if (it == body.end()) return fallback;
  if (!it->is_number_integer() || *it < min || *it > max) {
    throw InputError(key, 0, "expected a whole number " + std::to_string(min) + "…" + std::to_string(max) + ", found " +
                                 it->dump().substr(0, 40));
  }
  return it->get<int>();
}

// "3,4,5" → channel indices, each < count; nullopt for anything else.
std::optional<std::vector<int>> ParseIds(const std::string& text, int count) {
  std::vector<int> ids;
  const char* at = text.data();
  const char* end = text.data() + text.size();
  while (at < end) {
    int id = -1;
    const auto [next, error] = std::from_chars(at, end, id);
    if (error != std::errc() || id < 0 || id >= count || ids.size() >= kMaxChannelsPerRequest) return std::nullopt;
    ids.push_back(id);
    at = next;
    if (at < end && *at++ != ',') return std::nullopt;
  }
  if (ids.empty()) return std::nullopt;
  return ids;
}

nlohmann::json ContactsJson(const std::vector<evaluation::ContactSample>& contacts, std::size_t from, std::size_t to) {
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t k = from; k < to; ++k) {
    const evaluation::ContactSample& c = contacts[k];
    list.push_back({c.body1, c.body2, c.position[0], c.position[1], c.position[2], c.normal[0], c.normal[1],
                    c.normal[2], c.depth});
  }
  return list;
}

// A connection held in memory: reads come from the given bytes (then end of stream), writes are collected.
class StringStream : public httplib::Stream {
 public:
  explicit StringStream(std::string_view input) : input_(input) {}
  bool is_readable() const override { return position_ < input_.size(); }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    const std::size_t n = std::min(size, input_.size() - position_);
    std::memcpy(ptr, input_.data() + position_, n);
    position_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    output_.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 1;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 2;
  }
  socket_t socket() const override { return INVALID_SOCKET; }
  bool at_end() const { return position_ >= input_.size(); }
  std::string& output() { return output_; }

 private:
  std::string_view input_;
  std::size_t position_ = 0;
  std::string output_;
};

// A state-changing request is a JSON one: a page of another site can send "Content-Type: application/json" only
// after a CORS preflight, which orcs-view refuses (its Origin is foreign). 415 otherwise.
bool IsJsonRequest(const Request& request, Response& response) {
  const std::string type = text::ToLower(request.get_header_value("Content-Type"));
  if (type == "application/json" || type.starts_with("application/json;")) return true;
  SendError(response, 415, "Content-Type: expected application/json, found " + text::Quote(type));
  return false;
}

// A mutating live route: it needs the control token (X-Orcs-Token), else it answers 403, and a JSON object body.
template <typename Handler>
httplib::Server::Handler Controlled(LiveSession* live, Handler handler) {
  return [live, handler](const Request& request, Response& response) {
    if (!live->Controls(request.get_header_value("X-Orcs-Token"))) {
      return SendError(response, 403, "this page does not hold control: take control first");
    }
    if (!IsJsonRequest(request, response)) return;
    const std::optional<nlohmann::json> body = BodyObject(request, response);
    if (body) handler(*body, response);
  };
}

// A Host header's (or an Origin's, after "http://") name and port: the name in lower case, an IPv6 address in
// brackets, the port 80 when none is given. nullopt for anything else.
struct HostPort {
  std::string name;
  int port = 80;
};

std::optional<HostPort> ParseHostPort(std::string_view text) {
  const std::string lower = text::ToLower(text);
  std::string_view rest = lower;
  HostPort parsed;
  if (rest.starts_with('[')) {
    const std::size_t close = rest.find(']');
    if (close == std::string_view::npos) return std::nullopt;
    in6_addr address{};
    if (inet_pton(AF_INET6, std::string(rest.substr(1, close - 1)).c_str(), &address) != 1) return std::nullopt;
    parsed.name = std::string(rest.substr(0, close + 1));
    rest.remove_prefix(close + 1);
  } else {
    const std::size_t colon = rest.find(':');
    parsed.name = std::string(rest.substr(0, colon));
    rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon);
    const bool plain = std::all_of(parsed.name.begin(), parsed.name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_';
    });
    if (parsed.name.empty() || !plain) return std::nullopt;
  }
  if (!rest.empty()) {
    if (rest.front() != ':' || rest.size() < 2 || rest.size() > 6) return std::nullopt;
    const auto [end, error] = std::from_chars(rest.data() + 1, rest.data() + rest.size(), parsed.port);
    if (error != std::errc() || end != rest.data() + rest.size() || parsed.port < 1 || parsed.port > 65535) {
      return std::nullopt;
    }
  }
  return parsed;
}

// An address rather than a name: what DNS rebinding cannot point elsewhere.
bool IsAddressLiteral(const std::string& name) {
  if (name.starts_with('[')) return true;  // ParseHostPort checked it
  in_addr address{};
  return inet_pton(AF_INET, name.c_str(), &address) == 1;
}

// The one header of that name, "" for none; nullopt when there are several (refused).
std::optional<std::optional<std::string>> SingleHeader(const Request& request, const char* name) {
  const std::size_t count = request.get_header_value_count(name);
  if (count > 1) return std::nullopt;
  if (count == 0) return std::optional<std::string>();
  return std::optional<std::string>(request.get_header_value(name));
}

}  // namespace

// httplib's server with its per-request entry (protected there) made callable on a Stream.
class HttpServer : public httplib::Server {
 public:
  using httplib::Server::process_request;
};

ViewServer::ViewServer(const WebAssets& assets, ViewCatalog* catalog, LiveSession* live, RenderSink* render,
                       BrokerWatch* broker)
    : assets_(assets),
      catalog_(catalog),
      live_(live),
      render_(render),
      broker_(broker),
      server_(std::make_unique<HttpServer>()) {
  server_->new_task_queue = [] { return new httplib::ThreadPool(kServerThreads); };
  server_->set_payload_max_length(kMaxBodyBytes);
  // SO_REUSEADDR only: httplib's default adds SO_REUSEPORT, which would let a second orcs-view share a port that is
  // in use instead of being told so.
  server_->set_socket_options([](socket_t socket) {
    int yes = 1;
    setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  server_->set_read_timeout(kReadTimeoutSeconds, 0);
  server_->set_write_timeout(kWriteTimeoutSeconds, 0);
  server_->set_keep_alive_timeout(kKeepAliveTimeoutSeconds);
  server_->set_keep_alive_max_count(1000);
  // No page of another site may frame this one (clickjacking: "Take control" under someone else's button), embed
  // its answers (Cross-Origin-Resource-Policy), or read a mistyped answer as a script (nosniff).
  server_->set_default_headers({{"X-Frame-Options", "DENY"},
                                {"Content-Security-Policy", "frame-ancestors 'none'"},
                                {"Cross-Origin-Resource-Policy", "same-origin"},
                                {"X-Content-Type-Options", "nosniff"},
                                {"Referrer-Policy", "no-referrer"}});
  // Every request, before any route: only requests addressed to this server, from no page or from its own.
  server_->set_pre_routing_handler([this](const Request& request, Response& response) {
    const auto host = SingleHeader(request, "Host");
    const auto origin = SingleHeader(request, "Origin");
    const std::string refusal = !host ? "more than one Host header"
                                : !origin ? "more than one Origin header"
                                          : Refusal(*host, *origin);
    if (refusal.empty()) return httplib::Server::HandlerResponse::Unhandled;
    SendError(response, 403, refusal);
    return httplib::Server::HandlerResponse::Handled;
  });
  server_->set_exception_handler([](const Request&, Response& response, std::exception_ptr error) {
    try {
      std::rethrow_exception(error);
    } catch (const InputError& input) {
      SendError(response, 400, input.what());
    } catch (const std::exception& other) {
      SendError(response, 500, other.what());
    }
  });
  AddPageRoutes();
  if (catalog_ != nullptr) AddFilesRoutes();
  if (live_ != nullptr) AddLiveRoutes();
  if (render_ != nullptr) AddRenderRoutes();
  if (broker_ != nullptr) AddBrokerRoutes();
  server_->set_error_handler([](const Request&, Response& response) {
    if (response.body.empty()) {
      response.set_content(response.status == 404 ? "not found\n" : "bad request\n", "text/plain");
    }
  });
}

ViewServer::~ViewServer() = default;

int ViewServer::Bind(const std::string& address, int port) {
  const bool bound = port == 0 ? (port = server_->bind_to_any_port(address)) > 0 : server_->bind_to_port(address, port);
  if (!bound) {
    throw InputError("--port", 0, "cannot listen on " + address + ":" + std::to_string(port) +
                                      " (in use, or not an address of this machine): choose another with --port");
  }
  port_ = port;
  const std::string name = text::ToLower(address);
  if (name == "0.0.0.0" || name == "::" || name == "[::]") {
    any_address_ = true;
  } else {
    AllowHost(name.find(':') != std::string::npos && !name.starts_with('[') ? "[" + name + "]" : name);
  }
  return port;
}

void ViewServer::AllowHost(const std::string& name) {
  const std::string lower = text::ToLower(name);
  if (std::find(host_names_.begin(), host_names_.end(), lower) == host_names_.end()) host_names_.push_back(lower);
}

std::string ViewServer::Refusal(const std::optional<std::string>& host, const std::optional<std::string>& origin) const {
  const std::string port = port_ != 0 ? ":" + std::to_string(port_) : "";
  if (!host) return "no Host header: orcs-view answers only requests addressed to it, such as Host: 127.0.0.1" + port;
  const std::optional<HostPort> to = ParseHostPort(*host);
  const bool ours = to && (port_ == 0 || to->port == port_) &&
                    (std::find(host_names_.begin(), host_names_.end(), to->name) != host_names_.end() ||
                     (any_address_ && IsAddressLiteral(to->name)));
  if (!ours) {
    std::string names;
    for (const std::string& name : host_names_) names += (names.empty() ? "" : ", ") + name + port;
    if (any_address_) names += ", or an address of this machine" + port;
    return "Host " + text::Quote(*host) + " is not this server (" + names +
           "): refused, as a page of another site reaching it by DNS rebinding would be (--allow-host adds a name)";
  }
  if (origin) {
    const bool http = origin->size() > 7 && text::ToLower(origin->substr(0, 7)) == "http://";
    const std::optional<HostPort> from = http ? ParseHostPort(std::string_view(*origin).substr(7)) : std::nullopt;
    if (!from || from->name != to->name || from->port != to->port) {
      return "Origin " + text::Quote(*origin) + " is not this server's page (http://" + text::ToLower(*host) +
             "): requests from another site's page are refused";
    }
  }
  return "";
}

void ViewServer::Serve() { server_->listen_after_bind(); }
void ViewServer::Stop() { server_->stop(); }

std::vector<std::string> ViewServer::Answer(std::string_view bytes, int max_requests) {
  StringStream stream(bytes);
  std::vector<std::string> answers;
  for (int i = 0; i < max_requests && !stream.at_end(); ++i) {
    bool closed = false;
    const bool last = i + 1 == max_requests;
    const bool kept = server_->process_request(stream, last, closed, [](Request&) {});
    answers.push_back(std::move(stream.output()));
    stream.output().clear();
    if (!kept || closed) break;
  }
  return answers;
}

namespace {

// The page header's name for what is served: the top items' labels, at most three ("b1, swing +2 more").
std::string TitleOf(const nlohmann::json& items) {
  std::vector<std::string> labels;
  for (const nlohmann::json& item : items) {
    if (!item.contains("parent")) labels.push_back(item.value("label", item.value("id", "")));
  }
  std::string title;
  for (std::size_t i = 0; i < labels.size() && i < 3; ++i) title += (i ? ", " : "") + labels[i];
  if (labels.size() > 3) title += " +" + std::to_string(labels.size() - 3) + " more";
  return title;
}

}  // namespace

void ViewServer::AddPageRoutes() {
  server_->Get("/", [this](const Request&, Response& response) {
    const WebAsset* page = assets_.Find("index.html");
    response.set_content(page->content, page->content_type);
  });
  server_->Get(R"(/assets/([A-Za-z0-9_.-]+))", [this](const Request& request, Response& response) {
    const WebAsset* asset = assets_.Find(request.matches[1].str());
    if (asset == nullptr) {
      response.status = 404;
      return;
    }
    response.set_content(asset->content, asset->content_type);
  });
  server_->Get("/api/session", [this](const Request&, Response& response) {
    nlohmann::json session = {{"mode", live_ != nullptr ? "live" : "files"}, {"title", ""}};
    if (catalog_ != nullptr) session["items"] = catalog_->ItemsJson();
    session["title"] = live_ != nullptr ? live_->Title() : TitleOf(session.value("items", nlohmann::json::array()));
    if (live_ != nullptr) session["items"] = {{{"id", "live"}, {"kind", "live"}, {"label", "live simulation"}}};
    if (render_ != nullptr) session["render"] = true;
    if (broker_ != nullptr) {
      if (!session.contains("items")) session["items"] = nlohmann::json::array();
      const nlohmann::json dashboard = nlohmann::json::object({{"id", "broker"},
                                                               {"kind", "broker"},
                                                               {"label", "broker " + broker_->endpoint()},
                                                               {"path", broker_->endpoint()}});
      session["items"].insert(session["items"].begin(), dashboard);
    }
    SendJson(response, session);
  });
}

void ViewServer::AddFilesRoutes() {
  // Each handler looks the id up; an id that is not a recording answers 404.
  const auto recording_of = [this](const Request& request, Response& response) {
    std::shared_ptr<const evaluation::Recording> recording = catalog_->Recording(request.matches[1].str());
    if (recording == nullptr) SendError(response, 404, "no such recording");
    return recording;
  };
  server_->Get(R"(/api/recording/([A-Za-z0-9]+))", [this, recording_of](const Request& request, Response& response) {
    const auto recording = recording_of(request, response);
    if (!recording) return;
    nlohmann::json header = recording->header;
    header["frames"] = recording->frame_count();
    header["duration"] = recording->times.back();
    header["file"] = catalog_->Find(request.matches[1].str())->path;
    SendJson(response, header);
  });
  server_->Get(R"(/api/recording/([A-Za-z0-9]+)/times)", [recording_of](const Request& request, Response& response) {
    if (const auto recording = recording_of(request, response)) SendArray(response, recording->times);
  });
  server_->Get(R"(/api/recording/([A-Za-z0-9]+)/channels)", [recording_of](const Request& request,
                                                                           Response& response) {
    const auto recording = recording_of(request, response);
    if (!recording) return;
    const auto ids = ParseIds(request.get_param_value("ids"), recording->channel_count());
    if (!ids) return SendError(response, 400, "ids: expected channel indices such as 3,4,5 (at most 4096)");
    // frames=F: the first F frames only — a page that read the times of a recording still being written (orcs-robot
    // --view) asks for as many values as it has times, however far the file has grown since.
    std::size_t frames = static_cast<std::size_t>(recording->frame_count());
    if (request.has_param("frames")) {
      const std::string text = request.get_param_value("frames");
      std::size_t asked = 0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), asked);
      if (error != std::errc() || end != text.data() + text.size() || asked == 0 || asked > frames) {
        return SendError(response, 400, "frames: expected 1 to " + std::to_string(frames) + " (the frames read)");
      }
      frames = asked;
    }
    // Each id costs a column of every frame: bound the answer, not only the list (ids may repeat).
    if (ids->size() * frames > kMaxChannelValues) {
      return SendError(response, 400, "ids: at most " + std::to_string(kMaxChannelValues / std::max<std::size_t>(frames, 1)) +
                                          " channels of this recording (" + std::to_string(frames) +
                                          " frames) per request");
    }
    std::vector<float> columns;
    columns.reserve(ids->size() * frames);
    for (int id : *ids) {
      for (std::size_t f = 0; f < frames; ++f) columns.push_back(recording->value(static_cast<int>(f), id));
    }
    SendArray(response, columns);
  });
  server_->Get(R"(/api/recording/([A-Za-z0-9]+)/contacts)", [recording_of](const Request& request,
                                                                           Response& response) {
    const auto recording = recording_of(request, response);
    if (!recording) return;
    SendJson(response, {{"offsets", recording->contact_offsets},
                        {"contacts", ContactsJson(recording->contacts, 0, recording->contacts.size())}});
  });
  const auto table_route = [this](const char* pattern,
                                  std::optional<nlohmann::json> (ViewCatalog::*get)(std::string_view)) {
    server_->Get(pattern, [this, get](const Request& request, Response& response) {
      const std::optional<nlohmann::json> table = (catalog_->*get)(request.matches[1].str());
      if (!table) return SendError(response, 404, "no such item");
      SendJson(response, *table);
    });
  };
  table_route(R"(/api/batch/([A-Za-z0-9]+))", &ViewCatalog::BatchJson);
  table_route(R"(/api/evolve/([A-Za-z0-9]+))", &ViewCatalog::EvolveJson);
  table_route(R"(/api/gap/([A-Za-z0-9]+))", &ViewCatalog::GapJson);
  table_route(R"(/api/robot/([A-Za-z0-9]+))", &ViewCatalog::RobotJson);
  // The dashboard's links from a finished job to its replay.
  server_->Get("/api/replays", [this](const Request&, Response& response) {
    SendJson(response, {{"replays", catalog_->ReplaysJson()}});
  });
}

// The dashboard (orcs-view --broker): the broker's newest status, long-polled, and the history of its totals.
void ViewServer::AddBrokerRoutes() {
  server_->Get("/api/broker/status", [this](const Request& request, Response& response) {
    std::uint64_t since = 0;
    const std::string text = request.get_param_value("since");
    std::from_chars(text.data(), text.data() + text.size(), since);
    const BrokerWatch::Snapshot snapshot = broker_->Wait(since, long_poll_);
    nlohmann::json body = {{"serial", snapshot.serial},
                           {"time", snapshot.time},
                           {"endpoint", broker_->endpoint()},
                           {"error", snapshot.error},
                           {"status", nullptr}};
    if (!snapshot.status_json.empty()) body["status"] = nlohmann::json::parse(snapshot.status_json);
    SendJson(response, body);
  });
  server_->Get("/api/broker/history", [this](const Request&, Response& response) {
    nlohmann::json points = nlohmann::json::array();
    for (const BrokerWatch::Point& p : broker_->History()) {
      points.push_back({p.time, p.workers, p.busy, p.queued, p.running, p.done, p.failed, p.jobs_per_second});
    }
    SendJson(response, {{"endpoint", broker_->endpoint()},
                        {"columns", {"time", "workers", "busy", "queued", "running", "done", "failed", "jobs_per_second"}},
                        {"points", std::move(points)}});
  });
}

// The simulation: its world, its frames (long-polled), control and the run/pause/step/reset commands.
void ViewServer::AddLiveRoutes() {
  server_->Get("/api/live/world", [this](const Request&, Response& response) { SendJson(response, live_->world()); });
  server_->Get("/api/live/frame", [this](const Request& request, Response& response) {
    std::int64_t since = -1;
    const std::string text = request.get_param_value("since");
    std::from_chars(text.data(), text.data() + text.size(), since);
    const LiveFrame frame = live_->FrameAfter(since, long_poll_);
    nlohmann::json body = live_->State();
    body["serial"] = frame.serial;
    body["step"] = frame.step;
    body["time"] = frame.time;
    body["world_revision"] = frame.world_revision;
    body["controller"] = live_->Controls(request.get_header_value("X-Orcs-Token"));
    body["values"] = frame.values;
    body["contacts"] = ContactsJson(frame.contacts, 0, frame.contacts.size());
    SendJson(response, body);
  });
  // The token is handed only to a JSON request (no cross-site form can send one) from this server's own page (the
  // Origin and Host checks), and its answer is not stored anywhere.
  server_->Post("/api/live/claim", [this](const Request& request, Response& response) {
    if (!IsJsonRequest(request, response)) return;
    const std::string token = live_->Claim();
    if (token.empty()) return SendError(response, 409, "another page holds control");
    response.set_header("Cache-Control", "no-store");
    SendJson(response, {{"token", token}});
  });
  server_->Post("/api/live/control", Controlled(live_, [this](const nlohmann::json& body, Response& response) {
    live_->Control(StringField(body, "action"), BoolField(body, "realtime", true),
                   IntField(body, "steps", 1, 1, LiveSession::kMaxStepsAtOnce));
    SendJson(response, live_->State());
  }));
  AddLiveValueRoutes();
}

// The repository (Simulation Properties), value files and the Logger.
void ViewServer::AddLiveValueRoutes() {
  server_->Get("/api/live/values", [this](const Request& request, Response& response) {
    const std::string filter = request.has_param("filter") ? request.get_param_value("filter") : ".*";
    if (filter.size() > kMaxPatternLength) return SendError(response, 400, "filter: at most 1000 characters");
    SendJson(response, live_->Values(filter, kMaxValueRows));
  });
  server_->Post("/api/live/values", Controlled(live_, [this](const nlohmann::json& body, Response& response) {
    const std::string path = StringField(body, "path");
    const std::string value = live_->SetValue(path, StringField(body, "value"));
    SendJson(response, {{"path", path}, {"value", value}});
  }));
  server_->Post("/api/live/initial", Controlled(live_, [this](const nlohmann::json& body, Response& response) {
    live_->KeepPoseAsStart(StringField(body, "object"));
    SendJson(response, {{"object", StringField(body, "object")}});
  }));
  server_->Get("/api/live/files", [this](const Request&, Response& response) { SendJson(response, live_->Files()); });
  server_->Post("/api/live/save", Controlled(live_, [this](const nlohmann::json& body, Response& response) {
    const std::string filter = body.contains("filter") ? StringField(body, "filter") : ".*";
    live_->Save(StringField(body, "file"), filter);
    SendJson(response, {{"saved", StringField(body, "file")}});
  }));
  server_->Post("/api/live/load", Controlled(live_, [this](const nlohmann::json& body, Response& response) {
    live_->Load(StringField(body, "file"));
    SendJson(response, {{"loaded", StringField(body, "file")}});
  }));
  server_->Post("/api/live/logger", Controlled(live_, [this](const nlohmann::json& body, Response& response) {
    const std::string action = StringField(body, "action");
    if (action == "start") {
      live_->StartLogger(StringField(body, "filter"), StringField(body, "file"));
    } else if (action == "stop") {
      live_->StopLogger();
    } else {
      return SendError(response, 400, "action: expected start or stop");
    }
    SendJson(response, live_->State());
  }));
}

void ViewServer::AddRenderRoutes() {
  server_->Post("/api/render/frame", [this](const Request& request, Response& response) {
    int index = -1;
    const std::string text = request.get_param_value("index");
    std::from_chars(text.data(), text.data() + text.size(), index);
    if (!render_->AddFrame(index, request.body)) return SendError(response, 400, "expected a PNG frame and its index");
    SendJson(response, {{"stored", index}});
  });
  server_->Post("/api/render/done", [this](const Request& request, Response& response) {
    render_->Done(request.body);
    SendJson(response, {{"done", true}});
  });
}

}  // namespace orcs::viewer
