// CURVE key files: generation, the file format, and the clear one-line errors for every way a key folder can be
// wrong (each names the file).
#include "net/curve_keys.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <functional>

#include "tests/support/temp_dir.h"

namespace orcs::net {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

// The message of the CurveKeyError `action` throws; fails the test when it throws none.
std::string ErrorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const CurveKeyError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no CurveKeyError";
  return "";
}

unsigned ModeOf(const fs::path& file) {
  struct stat info {};
  EXPECT_EQ(::stat(file.c_str(), &info), 0) << file;
  return info.st_mode & 0777;
}

// A broker folder: broker, worker and client pairs; the worker's and the client's public keys allowed.
void MakeBrokerFolder(const TempDir& dir) {
  for (const char* name : {"broker", "worker", "client"}) WriteCurveKeyPair(dir.path(), name, GenerateCurveKeyPair());
  fs::create_directory(dir.path() / "allowed_workers");
  fs::create_directory(dir.path() / "allowed_clients");
  fs::copy_file(dir.path() / "worker.pub", dir.path() / "allowed_workers/worker.pub");
  fs::copy_file(dir.path() / "client.pub", dir.path() / "allowed_clients/client.pub");
}

TEST(CurveKeys, LibzmqHasCurve) { EXPECT_TRUE(CurveAvailable()); }

TEST(CurveKeys, WrittenPairReadsBackWithPrivateSecretFile) {
  TempDir dir;
  const CurveKeyPair pair = GenerateCurveKeyPair();
  EXPECT_EQ(pair.public_key.size(), 40u);
  EXPECT_NE(pair.public_key, pair.secret_key);
  WriteCurveKeyPair(dir.path() / "keys", "node-01", pair);
  const CurveKeyPair read = ReadCurveKeyPair(dir.path() / "keys", "node-01");
  EXPECT_EQ(read.public_key, pair.public_key);
  EXPECT_EQ(read.secret_key, pair.secret_key);
  EXPECT_EQ(ModeOf(dir.path() / "keys/node-01.key"), 0600u);
  EXPECT_EQ(ModeOf(dir.path() / "keys/node-01.pub"), 0644u);
  EXPECT_EQ(ModeOf(dir.path() / "keys"), 0700u);
  EXPECT_THAT(dir.Read("keys/node-01.pub"), HasSubstr(pair.public_key + "\n"));
  EXPECT_THAT(dir.Read("keys/node-01.pub"), Not(HasSubstr(pair.secret_key)));
  EXPECT_EQ(CurveKeyText(CurveKeyBytes(pair.public_key)), pair.public_key);
  EXPECT_FALSE(fs::exists(dir.path() / "keys/node-01.key.tmp"));
}

TEST(CurveKeys, TwoPairsDiffer) { EXPECT_NE(GenerateCurveKeyPair().secret_key, GenerateCurveKeyPair().secret_key); }

TEST(CurveKeys, NeverOverwritesAKeyFile) {
  TempDir dir;
  const CurveKeyPair first = GenerateCurveKeyPair();
  WriteCurveKeyPair(dir.path(), "worker", first);
  EXPECT_THAT(ErrorOf([&] { WriteCurveKeyPair(dir.path(), "worker", GenerateCurveKeyPair()); }),
              AllOf(HasSubstr((dir.path() / "worker.key").string()), HasSubstr("exists already")));
  EXPECT_EQ(ReadCurveKeyPair(dir.path(), "worker").secret_key, first.secret_key);
}

TEST(CurveKeys, RefusesNamesThatAreNotPlainFileNames) {
  TempDir dir;
  for (const char* name : {"", "../evil", ".hidden", "a b"}) {
    EXPECT_THAT(ErrorOf([&] { WriteCurveKeyPair(dir.path(), name, GenerateCurveKeyPair()); }),
                HasSubstr("key name"))
        << name;
  }
}

TEST(CurveKeys, CommentsAndBlankLinesAroundTheKeyAreIgnored) {
  TempDir dir;
  const CurveKeyPair pair = GenerateCurveKeyPair();
  const std::string file = dir.Write("a.pub", "# comment\n\n  " + pair.public_key + "  \r\n# another\n");
  EXPECT_EQ(ReadCurvePublicKey(file), pair.public_key);
}

TEST(CurveKeys, MalformedKeyFilesNameFileAndLine) {
  TempDir dir;
  const std::string key = GenerateCurveKeyPair().public_key;
  EXPECT_THAT(ErrorOf([&] { ReadCurvePublicKey(dir.PathOf("missing.pub")); }),
              AllOf(HasSubstr(dir.PathOf("missing.pub")), HasSubstr("no such file")));
  EXPECT_THAT(ErrorOf([&] { ReadCurvePublicKey(dir.Write("short.pub", "# c\nabc\n")); }),
              AllOf(HasSubstr(dir.PathOf("short.pub") + ": line 2: expected a 40-character Z85 key, found 3")));
  EXPECT_THAT(ErrorOf([&] { ReadCurvePublicKey(dir.Write("bad.pub", std::string(40, '~') + "\n")); }),
              AllOf(HasSubstr(dir.PathOf("bad.pub") + ": line 1: not Z85")));
  EXPECT_THAT(ErrorOf([&] { ReadCurvePublicKey(dir.Write("two.pub", key + "\n" + key + "\n")); }),
              HasSubstr(dir.PathOf("two.pub") + ": line 2: a second key (the first is on line 1)"));
  EXPECT_THAT(ErrorOf([&] { ReadCurvePublicKey(dir.Write("empty.pub", "# nothing\n")); }),
              HasSubstr(dir.PathOf("empty.pub") + ": holds no key"));
  EXPECT_THAT(ErrorOf([&] { ReadCurvePublicKey(dir.path()); }), HasSubstr("not a regular file"));
}

TEST(CurveKeys, SecretKeyOthersCanReadIsRefused) {
  TempDir dir;
  WriteCurveKeyPair(dir.path(), "client", GenerateCurveKeyPair());
  fs::permissions(dir.path() / "client.key", fs::perms::group_read, fs::perm_options::add);
  EXPECT_THAT(ErrorOf([&] { ReadCurveKeyPair(dir.path(), "client"); }),
              AllOf(HasSubstr((dir.path() / "client.key").string()), HasSubstr("mode 0640"), HasSubstr("chmod 600")));
}

TEST(CurveKeys, SecretAndPublicFromDifferentPairsAreRefused) {
  TempDir dir;
  WriteCurveKeyPair(dir.path(), "client", GenerateCurveKeyPair());
  WriteCurveKeyPair(dir.path(), "other", GenerateCurveKeyPair());
  fs::remove(dir.path() / "client.pub");
  fs::copy_file(dir.path() / "other.pub", dir.path() / "client.pub");
  EXPECT_THAT(ErrorOf([&] { ReadCurveKeyPair(dir.path(), "client"); }),
              AllOf(HasSubstr((dir.path() / "client.key").string()), HasSubstr("does not belong to"),
                    HasSubstr((dir.path() / "client.pub").string())));
}

TEST(CurveKeys, BrokerFolderLoadsAllowedKeysPerSide) {
  TempDir dir;
  MakeBrokerFolder(dir);
  const CurveBrokerKeys keys = LoadCurveBrokerKeys(dir.path());
  EXPECT_EQ(keys.own.public_key, ReadCurvePublicKey(dir.path() / "broker.pub"));
  ASSERT_EQ(keys.allowed_workers.size(), 1u);
  ASSERT_EQ(keys.allowed_clients.size(), 1u);
  EXPECT_EQ(keys.allowed_workers.begin()->first, CurveKeyBytes(ReadCurvePublicKey(dir.path() / "worker.pub")));
  EXPECT_EQ(keys.allowed_clients.begin()->first, CurveKeyBytes(ReadCurvePublicKey(dir.path() / "client.pub")));
  EXPECT_EQ(keys.allowed_clients.begin()->second, (dir.path() / "allowed_clients/client.pub").string());
}

TEST(CurveKeys, BrokerFolderErrorsNameTheFile) {
  TempDir dir;
  MakeBrokerFolder(dir);
  fs::rename(dir.path() / "allowed_workers", dir.path() / "workers");
  EXPECT_THAT(ErrorOf([&] { LoadCurveBrokerKeys(dir.path()); }),
              AllOf(HasSubstr((dir.path() / "allowed_workers").string()), HasSubstr("no such folder")));
  fs::rename(dir.path() / "workers", dir.path() / "allowed_workers");

  dir.Write("allowed_workers/broken.pub", "not a key\n");
  EXPECT_THAT(ErrorOf([&] { LoadCurveBrokerKeys(dir.path()); }), HasSubstr(dir.PathOf("allowed_workers/broken.pub")));
  fs::remove(dir.path() / "allowed_workers/broken.pub");

  fs::copy_file(dir.path() / "client.pub", dir.path() / "allowed_workers/client.pub");
  EXPECT_THAT(ErrorOf([&] { LoadCurveBrokerKeys(dir.path()); }), HasSubstr("a worker's or a client's, not both"));
  fs::remove(dir.path() / "allowed_workers/client.pub");

  fs::copy_file(dir.path() / "worker.pub", dir.path() / "allowed_workers/again.pub");
  EXPECT_THAT(ErrorOf([&] { LoadCurveBrokerKeys(dir.path()); }), HasSubstr("the same key as"));
  fs::remove(dir.path() / "allowed_workers/again.pub");

  fs::remove(dir.path() / "broker.key");
  EXPECT_THAT(ErrorOf([&] { LoadCurveBrokerKeys(dir.path()); }),
              AllOf(HasSubstr((dir.path() / "broker.key").string()), HasSubstr("no such file")));
}

TEST(CurveKeys, PeerFolderNeedsItsPairAndTheBrokersPublicKey) {
  TempDir dir;
  MakeBrokerFolder(dir);
  const CurvePeerKeys worker = LoadCurvePeerKeys(dir.path(), "worker");
  EXPECT_EQ(worker.own.public_key, ReadCurvePublicKey(dir.path() / "worker.pub"));
  EXPECT_EQ(worker.broker_public_key, ReadCurvePublicKey(dir.path() / "broker.pub"));
  fs::remove(dir.path() / "broker.pub");
  EXPECT_THAT(ErrorOf([&] { LoadCurvePeerKeys(dir.path(), "client"); }),
              AllOf(HasSubstr((dir.path() / "broker.pub").string()), HasSubstr("no such file")));
}

}  // namespace
}  // namespace orcs::net
