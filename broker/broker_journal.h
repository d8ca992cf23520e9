// The broker's journal (docs/protocol.md, "Journal"): every accepted job,
// dispatch and result, in an SQLite file in WAL mode, so that a broker killed
// (even with SIGKILL) and started again on the same file resumes where it
// stopped. The broker writes one transaction per turn of its loop; a turn lost
// in a crash is covered by the protocol itself (clients resubmit jobs without a
// result, workers send late results, duplicates are dropped).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "orcs/v1/broker.pb.h"

struct sqlite3;
struct sqlite3_stmt;

namespace orcs::broker {

/// One job as the journal holds it.
struct JournalJob {
  std::string batch_id;      ///< the batch it belongs to
  v1::Job job;               ///< as accepted (empty but for job_id once finished)
  bool dispatched = false;   ///< sent to a worker and not answered when last written
  bool finished = false;     ///< answered: BrokerJournal::Result() holds the answer
  int losses = 0;            ///< workers lost while holding it
  int dispatches = 0;        ///< JOB messages sent for it
  std::string lost_by;       ///< names of the workers lost while holding it, ", "-separated
  std::uint64_t ticket = 0;  ///< its place in the queue when last queued (smaller = earlier)
};

/// A batch as the journal holds it.
struct JournalBatch {
  std::string batch_id;   ///< Submit.batch_id
  std::string client_id;    ///< Submit.client_id of its owner
  std::string owner_token;  ///< Submit.owner_token of its first SUBMIT: only its holder may claim the batch
  std::string client_key;   ///< with CURVE, the owner's public key (Z85); "" without CURVE
};

/// The journal file. Not thread-safe: the broker's thread alone uses it.
class BrokerJournal {
 public:
  /// Opens (or creates) the journal at `path`. Throws std::runtime_error naming
  /// the file when it cannot be opened, is not an SQLite file, or holds a
  /// schema of another version.
  explicit BrokerJournal(const std::string &path);
  ~BrokerJournal();
  BrokerJournal(const BrokerJournal &) = delete;
  BrokerJournal &operator=(const BrokerJournal &) = delete;

  const std::string &path() const { return path_; }

  /// Every batch in the journal.
  std::vector<JournalBatch> Batches();
  /// Every job in the journal: those in flight first, then the queued ones in
  /// queue order, then the finished ones.
  void ForEachJob(const std::function<void(JournalJob &&)> &visit);
  /// The stored result of a finished job, if there is one.
  std::optional<v1::Result> Result(const std::string &batch_id, const std::string &job_id);

  /// Groups the writes that follow into one transaction, until Commit().
  void Begin();
  void Commit();

  void AddBatch(const std::string &batch_id, const std::string &client_id, const std::string &owner_token,
                const std::string &client_key);
  /// The job waits in the queue (accepted, or back after its worker was lost).
  void SaveQueued(const std::string &batch_id, const v1::Job &job, std::uint64_t ticket, int losses,
                  const std::string &lost_by);
  /// The job went to a worker.
  void SaveDispatched(const std::string &batch_id, const std::string &job_id, int dispatches);
  /// The job is answered; the result is kept until its batch is dropped, for a
  /// client that asks again.
  void SaveFinished(const std::string &batch_id, const std::string &job_id, const v1::Result &result);
  /// Forgets a batch and its jobs.
  void DropBatch(const std::string &batch_id);

 private:
  void Open();
  void Close();
  void Execute(const char *sql);
  sqlite3_stmt *Prepare(const char *sql);
  void Step(sqlite3_stmt *statement, const char *what);
  [[noreturn]] void Fail(const std::string &what);

  std::string path_;
  sqlite3 *db_ = nullptr;
  bool in_transaction_ = false;
  sqlite3_stmt *add_batch_ = nullptr;
  sqlite3_stmt *save_queued_ = nullptr;
  sqlite3_stmt *save_dispatched_ = nullptr;
  sqlite3_stmt *save_finished_ = nullptr;
  sqlite3_stmt *drop_jobs_ = nullptr;
  sqlite3_stmt *drop_batch_ = nullptr;
  sqlite3_stmt *result_ = nullptr;
  std::string buffer_;  ///< reused for serialising
};

}  // namespace orcs::broker
