#include "broker/broker_journal.h"

#include <fcntl.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <stdexcept>

namespace orcs::broker {
namespace {

// Bumped whenever the tables change; a journal of another version is refused
// rather than misread.
constexpr int kSchemaVersion = 2;  // 2: batches record their owner's token and CURVE key

// State of a job row.
constexpr int kQueued = 0;
constexpr int kDispatched = 1;
constexpr int kFinished = 2;

constexpr const char *kSchema = R"sql(
CREATE TABLE IF NOT EXISTS batches (
  batch_id TEXT PRIMARY KEY,
  client_id TEXT NOT NULL,
  owner_token BLOB NOT NULL,
  client_key TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS jobs (
  batch_id TEXT NOT NULL,
  job_id TEXT NOT NULL,
  state INTEGER NOT NULL,
  job BLOB,
  result BLOB,
  losses INTEGER NOT NULL DEFAULT 0,
  dispatches INTEGER NOT NULL DEFAULT 0,
  lost_by TEXT NOT NULL DEFAULT '',
  ticket INTEGER NOT NULL DEFAULT 0,
  PRIMARY KEY (batch_id, job_id)
);
)sql";

std::string Text(sqlite3_stmt *statement, int column) {
  const auto *text = sqlite3_column_text(statement, column);
  return text == nullptr ? std::string()
                         : std::string(reinterpret_cast<const char *>(text),
                                       static_cast<std::size_t>(sqlite3_column_bytes(statement, column)));
}

std::string Blob(sqlite3_stmt *statement, int column) {
  const void *data = sqlite3_column_blob(statement, column);
  return data == nullptr ? std::string()
                         : std::string(static_cast<const char *>(data),
                                       static_cast<std::size_t>(sqlite3_column_bytes(statement, column)));
}

template <typename Message>
bool ParseBlob(sqlite3_stmt *statement, int column, Message &message) {
  const void *data = sqlite3_column_blob(statement, column);
  const int size = sqlite3_column_bytes(statement, column);
  if (data == nullptr) return size == 0 && (message.Clear(), true);
  return message.ParseFromArray(data, size);
}

}  // namespace

BrokerJournal::BrokerJournal(const std::string &path) : path_(path) {
  try {
    Open();
  } catch (...) {
    Close();
    throw;
  }
}

void BrokerJournal::Open() {
  // The journal holds batch owners' tokens: readable by the broker's user only. SQLite gives its -wal and -shm
  // files the database file's permissions.
  const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
  if (fd < 0) Fail(std::string("cannot open: ") + std::strerror(errno));
  struct stat info {};
  const bool regular = ::fstat(fd, &info) == 0 && S_ISREG(info.st_mode);
  if (regular && (info.st_mode & 077) != 0) ::fchmod(fd, 0600);
  ::close(fd);
  if (!regular) Fail("not a regular file");
  if (sqlite3_open_v2(path_.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr) !=
      SQLITE_OK) {
    Fail("cannot open");
  }
  sqlite3_busy_timeout(db_, 2000);
  // WAL: a commit is one append to the log; synchronous=NORMAL keeps every
  // commit of a process that is killed (only a power cut may lose the last
  // ones, which the protocol's resubmissions cover).
  Execute("PRAGMA journal_mode=WAL");
  Execute("PRAGMA synchronous=NORMAL");
  sqlite3_stmt *version = Prepare("PRAGMA user_version");
  const int found = sqlite3_step(version) == SQLITE_ROW ? sqlite3_column_int(version, 0) : 0;
  sqlite3_finalize(version);
  if (found != 0 && found != kSchemaVersion) {
    Fail("holds a journal of schema version " + std::to_string(found) + " (this broker writes version " +
         std::to_string(kSchemaVersion) + ")");
  }
  Execute(kSchema);
  Execute(("PRAGMA user_version=" + std::to_string(kSchemaVersion)).c_str());
  add_batch_ = Prepare(
      "INSERT OR REPLACE INTO batches (batch_id, client_id, owner_token, client_key) VALUES (?1, ?2, ?3, ?4)");
  save_queued_ = Prepare(
      "INSERT INTO jobs (batch_id, job_id, state, job, "
      "result, losses, dispatches, lost_by, ticket) "
      "VALUES (?1, ?2, 0, ?3, NULL, ?4, 0, ?5, ?6) ON "
      "CONFLICT (batch_id, job_id) DO UPDATE SET "
      "state = 0, job = excluded.job, result = NULL, losses "
      "= excluded.losses, lost_by = excluded.lost_by, "
      "ticket = excluded.ticket");
  save_dispatched_ = Prepare(
      "UPDATE jobs SET state = 1, dispatches = ?3 WHERE "
      "batch_id = ?1 AND job_id = ?2");
  save_finished_ = Prepare(
      "UPDATE jobs SET state = 2, job = NULL, result = ?3 "
      "WHERE batch_id = ?1 AND job_id = ?2");
  drop_jobs_ = Prepare("DELETE FROM jobs WHERE batch_id = ?1");
  drop_batch_ = Prepare("DELETE FROM batches WHERE batch_id = ?1");
  result_ = Prepare(
      "SELECT result FROM jobs WHERE batch_id = ?1 AND job_id = "
      "?2 AND state = 2");
}

BrokerJournal::~BrokerJournal() { Close(); }

void BrokerJournal::Close() {
  for (sqlite3_stmt *statement :
       {add_batch_, save_queued_, save_dispatched_, save_finished_, drop_jobs_, drop_batch_, result_}) {
    sqlite3_finalize(statement);  // a null statement is a no-op
  }
  // Only what was committed counts, as when the broker is killed; the broker commits every turn it completes.
  if (in_transaction_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  in_transaction_ = false;
  sqlite3_close(db_);  // a null handle is a no-op
  db_ = nullptr;
}

std::vector<JournalBatch> BrokerJournal::Batches() {
  std::vector<JournalBatch> batches;
  sqlite3_stmt *select = Prepare("SELECT batch_id, client_id, owner_token, client_key FROM batches ORDER BY rowid");
  while (sqlite3_step(select) == SQLITE_ROW) {
    batches.push_back({Text(select, 0), Text(select, 1), Blob(select, 2), Text(select, 3)});
  }
  sqlite3_finalize(select);
  return batches;
}

void BrokerJournal::ForEachJob(const std::function<void(JournalJob &&)> &visit) {
  sqlite3_stmt *select = Prepare(
      "SELECT batch_id, job_id, state, job, losses, "
      "dispatches, lost_by, ticket FROM jobs "
      "ORDER BY CASE state WHEN 1 THEN 0 WHEN 0 "
      "THEN 1 ELSE 2 END, ticket, rowid");
  int status = SQLITE_ROW;
  while ((status = sqlite3_step(select)) == SQLITE_ROW) {
    JournalJob job;
    job.batch_id = Text(select, 0);
    const int state = sqlite3_column_int(select, 2);
    if (state != kFinished && !ParseBlob(select, 3, job.job)) {
      const std::string where = "job '" + Text(select, 1) + "' of batch '" + job.batch_id + "'";
      sqlite3_finalize(select);
      Fail(where + " does not parse");
    }
    job.job.set_job_id(Text(select, 1));
    job.dispatched = state == kDispatched;
    job.finished = state == kFinished;
    job.losses = sqlite3_column_int(select, 4);
    job.dispatches = sqlite3_column_int(select, 5);
    job.lost_by = Text(select, 6);
    job.ticket = static_cast<std::uint64_t>(sqlite3_column_int64(select, 7));
    visit(std::move(job));
  }
  sqlite3_finalize(select);
  if (status != SQLITE_DONE) Fail("cannot read its jobs");
}

std::optional<v1::Result> BrokerJournal::Result(const std::string &batch_id, const std::string &job_id) {
  sqlite3_bind_text(result_, 1, batch_id.data(), static_cast<int>(batch_id.size()), SQLITE_STATIC);
  sqlite3_bind_text(result_, 2, job_id.data(), static_cast<int>(job_id.size()), SQLITE_STATIC);
  std::optional<v1::Result> found;
  if (sqlite3_step(result_) == SQLITE_ROW) {
    v1::Result result;
    if (ParseBlob(result_, 0, result)) found = std::move(result);
  }
  sqlite3_reset(result_);
  return found;
}

void BrokerJournal::Begin() {
  if (in_transaction_) return;
  Execute("BEGIN");
  in_transaction_ = true;
}

void BrokerJournal::Commit() {
  if (!in_transaction_) return;
  in_transaction_ = false;
  Execute("COMMIT");
}

void BrokerJournal::AddBatch(const std::string &batch_id, const std::string &client_id, const std::string &owner_token,
                            const std::string &client_key) {
  sqlite3_bind_text(add_batch_, 1, batch_id.data(), static_cast<int>(batch_id.size()), SQLITE_STATIC);
  sqlite3_bind_text(add_batch_, 2, client_id.data(), static_cast<int>(client_id.size()), SQLITE_STATIC);
  sqlite3_bind_blob(add_batch_, 3, owner_token.data(), static_cast<int>(owner_token.size()), SQLITE_STATIC);
  sqlite3_bind_text(add_batch_, 4, client_key.data(), static_cast<int>(client_key.size()), SQLITE_STATIC);
  Step(add_batch_, "record a batch");
}

void BrokerJournal::SaveQueued(const std::string &batch_id, const v1::Job &job, std::uint64_t ticket, int losses,
                               const std::string &lost_by) {
  buffer_.clear();
  job.SerializeToString(&buffer_);
  sqlite3_bind_text(save_queued_, 1, batch_id.data(), static_cast<int>(batch_id.size()), SQLITE_STATIC);
  sqlite3_bind_text(save_queued_, 2, job.job_id().data(), static_cast<int>(job.job_id().size()), SQLITE_STATIC);
  sqlite3_bind_blob(save_queued_, 3, buffer_.data(), static_cast<int>(buffer_.size()), SQLITE_STATIC);
  sqlite3_bind_int(save_queued_, 4, losses);
  sqlite3_bind_text(save_queued_, 5, lost_by.data(), static_cast<int>(lost_by.size()), SQLITE_STATIC);
  sqlite3_bind_int64(save_queued_, 6, static_cast<sqlite3_int64>(ticket));
  Step(save_queued_, "record a queued job");
}

void BrokerJournal::SaveDispatched(const std::string &batch_id, const std::string &job_id, int dispatches) {
  sqlite3_bind_text(save_dispatched_, 1, batch_id.data(), static_cast<int>(batch_id.size()), SQLITE_STATIC);
  sqlite3_bind_text(save_dispatched_, 2, job_id.data(), static_cast<int>(job_id.size()), SQLITE_STATIC);
  sqlite3_bind_int(save_dispatched_, 3, dispatches);
  Step(save_dispatched_, "record a dispatch");
}

void BrokerJournal::SaveFinished(const std::string &batch_id, const std::string &job_id, const v1::Result &result) {
  buffer_.clear();
  result.SerializeToString(&buffer_);
  sqlite3_bind_text(save_finished_, 1, batch_id.data(), static_cast<int>(batch_id.size()), SQLITE_STATIC);
  sqlite3_bind_text(save_finished_, 2, job_id.data(), static_cast<int>(job_id.size()), SQLITE_STATIC);
  sqlite3_bind_blob(save_finished_, 3, buffer_.data(), static_cast<int>(buffer_.size()), SQLITE_STATIC);
  Step(save_finished_, "record a result");
}

void BrokerJournal::DropBatch(const std::string &batch_id) {
  for (sqlite3_stmt *statement : {drop_jobs_, drop_batch_}) {
    sqlite3_bind_text(statement, 1, batch_id.data(), static_cast<int>(batch_id.size()), SQLITE_STATIC);
    Step(statement, "drop a batch");
  }
}

void BrokerJournal::Execute(const char *sql) {
  char *message = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string why = message != nullptr ? message : "unknown error";
    sqlite3_free(message);
    Fail(why);
  }
}

sqlite3_stmt *BrokerJournal::Prepare(const char *sql) {
  sqlite3_stmt *statement = nullptr;
  if (sqlite3_prepare_v2(db_, sql, -1, &statement, nullptr) != SQLITE_OK) Fail(sqlite3_errmsg(db_));
  return statement;
}

// Runs a write statement to its end and makes it ready for the next bind.
void BrokerJournal::Step(sqlite3_stmt *statement, const char *what) {
  const int status = sqlite3_step(statement);
  sqlite3_reset(statement);
  sqlite3_clear_bindings(statement);
  if (status != SQLITE_DONE && status != SQLITE_ROW) Fail(std::string("cannot ") + what + ": " + sqlite3_errmsg(db_));
}

void BrokerJournal::Fail(const std::string &what) {
  std::string message = "journal " + path_ + ": " + what;
  if (db_ != nullptr && what.find(sqlite3_errmsg(db_)) == std::string::npos && sqlite3_errcode(db_) != SQLITE_OK) {
    message += " (" + std::string(sqlite3_errmsg(db_)) + ")";
  }
  throw std::runtime_error(message);
}

}  // namespace orcs::broker
