#include "net/curve_keys.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zmq.h>

#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <vector>

namespace orcs::net {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kZ85KeyLength = 40;   // Z85 text of a 32-byte key
constexpr std::size_t kKeyBytes = 32;       // a CURVE key
constexpr std::uintmax_t kMaxKeyFileBytes = 4096;  // a key file is one line and a few comments

[[noreturn]] void Fail(const fs::path& file, const std::string& what) {
  throw CurveKeyError(file.string() + ": " + what);
}

std::string Trimmed(const std::string& line) {
  const auto first = line.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
}

bool IsZ85Key(const std::string& text) {
  if (text.size() != kZ85KeyLength) return false;
  std::uint8_t bytes[kKeyBytes];
  return zmq_z85_decode(bytes, text.c_str()) != nullptr;
}

// The one key line of `file`, checked to be a Z85 key.
std::string ReadKeyLine(const fs::path& file) {
  std::error_code error;
  const fs::file_status status = fs::status(file, error);
  if (error || !fs::exists(status)) Fail(file, "no such file");
  if (!fs::is_regular_file(status)) Fail(file, "not a regular file");
  if (fs::file_size(file, error) > kMaxKeyFileBytes) Fail(file, "too large for a key file (over 4 KiB)");
  std::ifstream in(file);
  if (!in) Fail(file, std::string("cannot read: ") + std::strerror(errno));
  std::string key;
  int key_line = 0;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string text = Trimmed(line);
    if (text.empty() || text[0] == '#') continue;
    const std::string where = "line " + std::to_string(number) + ": ";
    if (key_line != 0) Fail(file, where + "a second key (the first is on line " + std::to_string(key_line) + ")");
    if (text.size() != kZ85KeyLength) {
      Fail(file, where + "expected a 40-character Z85 key, found " + std::to_string(text.size()) + " characters");
    }
    if (!IsZ85Key(text)) Fail(file, where + "not Z85 text (ZeroMQ's key encoding)");
    key = text;
    key_line = number;
  }
  if (key_line == 0) Fail(file, "holds no key");
  return key;
}

void RequirePrivate(const fs::path& file) {
  struct stat info {};
  if (::stat(file.c_str(), &info) != 0) Fail(file, std::string("cannot stat: ") + std::strerror(errno));
  if ((info.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(info.st_mode & 07777));
    Fail(file, std::string("a secret key others can read (mode ") + mode + "); chmod 600 it");
  }
}

void CheckName(const std::string& name) {
  bool ok = !name.empty() && name[0] != '.';
  for (char c : name) {
    ok = ok && (std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '_' || c == '-');
  }
  if (!ok) {
    throw CurveKeyError("key name '" + name + "': use letters, digits, '.', '_' and '-', not starting with '.'");
  }
}

// Writes `text` to `file` through a temporary name; refuses to replace an existing file.
void WriteNewFile(const fs::path& file, const std::string& text, mode_t mode) {
  const fs::path temporary = file.string() + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
  if (fd < 0) Fail(temporary, std::string("cannot create: ") + std::strerror(errno));
  const bool written = ::fchmod(fd, mode) == 0 &&  // the umask must not widen or narrow it
                       ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  // link() fails when `file` exists, where rename() would replace it.
  if (!written || ::link(temporary.c_str(), file.c_str()) != 0) {
    const int cause = written ? errno : saved;
    ::unlink(temporary.c_str());
    Fail(file, std::string("cannot write: ") + std::strerror(cause));
  }
  ::unlink(temporary.c_str());
}

AllowedCurveKeys ReadAllowedKeys(const fs::path& folder, const char* role) {
  std::error_code error;
  if (!fs::is_directory(folder, error)) {
    Fail(folder, std::string("no such folder (it holds the public keys of the ") + role + " allowed to connect)");
  }
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    if (entry.path().extension() == ".pub") files.push_back(entry.path());
  }
  if (error) Fail(folder, "cannot list: " + error.message());
  AllowedCurveKeys allowed;
  for (const fs::path& file : files) {
    const std::string bytes = CurveKeyBytes(ReadKeyLine(file));
    auto [existing, inserted] = allowed.emplace(bytes, file.string());
    if (!inserted) Fail(file, "the same key as " + existing->second);
  }
  return allowed;
}

}  // namespace

bool CurveAvailable() { return zmq_has("curve") != 0; }

void RequireCurve() {
  if (CurveAvailable()) return;
  int major = 0, minor = 0, patch = 0;
  zmq_version(&major, &minor, &patch);
  throw CurveKeyError("this libzmq (" + std::to_string(major) + "." + std::to_string(minor) + "." +
                      std::to_string(patch) +
                      ") was built without CURVE (libsodium); --curve-keys needs one with it, e.g. Debian's libzmq5");
}

CurveKeyPair GenerateCurveKeyPair() {
  RequireCurve();
  char public_key[kZ85KeyLength + 1];
  char secret_key[kZ85KeyLength + 1];
  if (zmq_curve_keypair(public_key, secret_key) != 0) {
    throw CurveKeyError(std::string("cannot generate a CURVE key pair: ") + zmq_strerror(zmq_errno()));
  }
  return {public_key, secret_key};
}

void WriteCurveKeyPair(const fs::path& dir, const std::string& name, const CurveKeyPair& pair) {
  CheckName(name);
  if (!IsZ85Key(pair.public_key) || !IsZ85Key(pair.secret_key)) throw CurveKeyError("not a Z85 key pair");
  std::error_code error;
  if (!fs::exists(dir, error)) {
    fs::create_directories(dir, error);
    if (error) Fail(dir, "cannot create: " + error.message());
    fs::permissions(dir, fs::perms::owner_all, error);
  }
  const fs::path secret = dir / (name + ".key");
  const fs::path open = dir / (name + ".pub");
  for (const fs::path& file : {secret, open}) {
    if (fs::exists(fs::symlink_status(file, error))) Fail(file, "exists already; not overwritten");
  }
  WriteNewFile(secret, "# orcs CURVE secret key '" + name + "': keep it on this machine, readable by its owner only\n" +
                           pair.secret_key + "\n",
               0600);
  WriteNewFile(open, "# orcs CURVE public key '" + name + "'\n" + pair.public_key + "\n", 0644);
}

std::string ReadCurvePublicKey(const fs::path& file) { return ReadKeyLine(file); }

CurveKeyPair ReadCurveKeyPair(const fs::path& dir, const std::string& name) {
  const fs::path secret_file = dir / (name + ".key");
  const fs::path public_file = dir / (name + ".pub");
  CurveKeyPair pair;
  pair.secret_key = ReadKeyLine(secret_file);
  RequirePrivate(secret_file);
  pair.public_key = ReadKeyLine(public_file);
  char derived[kZ85KeyLength + 1];
  if (zmq_curve_public(derived, pair.secret_key.c_str()) != 0 || pair.public_key != derived) {
    Fail(secret_file, "does not belong to " + public_file.string() + " (not one key pair)");
  }
  return pair;
}

CurveBrokerKeys LoadCurveBrokerKeys(const fs::path& dir) {
  RequireCurve();
  CurveBrokerKeys keys;
  keys.own = ReadCurveKeyPair(dir, "broker");
  keys.allowed_workers = ReadAllowedKeys(dir / "allowed_workers", "workers");
  keys.allowed_clients = ReadAllowedKeys(dir / "allowed_clients", "clients");
  for (const auto& [bytes, file] : keys.allowed_clients) {
    auto worker = keys.allowed_workers.find(bytes);
    if (worker != keys.allowed_workers.end()) {
      throw CurveKeyError(file + ": the same key as " + worker->second +
                          "; a key is a worker's or a client's, not both");
    }
  }
  return keys;
}

CurvePeerKeys LoadCurvePeerKeys(const fs::path& dir, const std::string& role) {
  RequireCurve();
  CurvePeerKeys keys;
  keys.own = ReadCurveKeyPair(dir, role);
  keys.broker_public_key = ReadKeyLine(dir / "broker.pub");
  return keys;
}

void MakeCurveServer(zmq::socket_t& socket, const CurveKeyPair& own, const std::string& zap_domain) {
  socket.set(zmq::sockopt::curve_server, true);
  socket.set(zmq::sockopt::curve_secretkey, own.secret_key);
  socket.set(zmq::sockopt::zap_domain, zap_domain);
}

void MakeCurveClient(zmq::socket_t& socket, const CurvePeerKeys& keys) {
  socket.set(zmq::sockopt::curve_serverkey, keys.broker_public_key);
  socket.set(zmq::sockopt::curve_publickey, keys.own.public_key);
  socket.set(zmq::sockopt::curve_secretkey, keys.own.secret_key);
}

std::string CurveKeyBytes(const std::string& z85) {
  std::string bytes(kKeyBytes, '\0');
  if (z85.size() != kZ85KeyLength ||
      zmq_z85_decode(reinterpret_cast<std::uint8_t*>(bytes.data()), z85.c_str()) == nullptr) {
    throw CurveKeyError("not a Z85 key: '" + z85 + "'");
  }
  return bytes;
}

std::string CurveKeyText(const std::string& bytes) {
  if (bytes.size() != kKeyBytes) throw CurveKeyError("a CURVE key has 32 bytes, not " + std::to_string(bytes.size()));
  char text[kZ85KeyLength + 1];
  zmq_z85_encode(text, reinterpret_cast<const std::uint8_t*>(bytes.data()), kKeyBytes);
  return text;
}

}  // namespace orcs::net
