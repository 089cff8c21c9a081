// SPDX-License-Identifier: MIT
/// @brief Roles and key pairs on disk (robot/link/trust), and `telesphere-keys` itself: pairs made
///        by libzmq round-trip through their files; a secret key others may read, a public key
///        that does not match its secret, a bad name or role are refused with the path and the
///        fix; an existing key is not replaced without --force.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "robot/link/trust/link_key_files.h"
#include "robot/link/trust/link_key_pair.h"

namespace telesphere::link::trust {
namespace {

namespace fs = std::filesystem;

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("telesphere-keys-" + std::to_string(::getpid()) + "-" +
                                               ::testing::UnitTest::GetInstance()->current_test_info()->name());
  TempDir() { fs::remove_all(path); }
  ~TempDir() { fs::remove_all(path); }
};

unsigned modeOf(const fs::path& p) {
  struct stat st {};
  ::stat(p.c_str(), &st);
  return st.st_mode & 0777;
}

TEST(LinkRole, NamesRoundTripAndNothingElseParses) {
  for (const LinkRole r : {LinkRole::kRobot, LinkRole::kOperator, LinkRole::kSupervisor, LinkRole::kViewer})
    EXPECT_EQ(parseLinkRole(linkRoleName(r)), r);
  EXPECT_FALSE(parseLinkRole("Operator"));
  EXPECT_FALSE(parseLinkRole(""));
  EXPECT_FALSE(parseLinkRole("admin"));
  EXPECT_EQ(linkRoleChoices(), "robot|operator|supervisor|viewer");
}

TEST(LinkKeyPair, LibzmqMakesDistinctPairsWhosePublicKeyFollowsFromTheSecret) {
  ASSERT_TRUE(curveAvailable()) << "Debian's libzmq is built with libsodium";
  std::string error;
  const auto a = generateKeyPair("rig-pc", LinkRole::kRobot, &error);
  const auto b = generateKeyPair("rig-pc", LinkRole::kRobot, &error);
  ASSERT_TRUE(a && b) << error;
  EXPECT_EQ(a->key.public_z85.size(), 40u);
  EXPECT_EQ(a->secret_z85.size(), 40u);
  EXPECT_NE(a->secret_z85, b->secret_z85);
  EXPECT_EQ(publicKeyOf(a->secret_z85), a->key.public_z85);
  EXPECT_FALSE(publicKeyOf("too short"));
  EXPECT_FALSE(publicKeyOf(std::string(40, '"')));  // not Z85
}

TEST(LinkKeyPair, BadNamesAreRefusedWithTheReason) {
  std::string error;
  for (const std::string& name : std::vector<std::string>{"", ".hidden", "a/b", "op erator", std::string(65, 'x'), "caf\xc3\xa9"}) {
    EXPECT_FALSE(generateKeyPair(name, LinkRole::kOperator, &error)) << name;
    EXPECT_FALSE(error.empty());
  }
  EXPECT_EQ(checkKeyName("Operator_1.lab-B"), "");
  EXPECT_EQ(checkKeyName(std::string(64, 'x')), "");
}

TEST(LinkKeyFiles, APairRoundTripsWithTheSecretKeptFromOthers) {
  TempDir dir;
  std::string error;
  const auto pair = generateKeyPair("alice", LinkRole::kOperator, &error);
  ASSERT_TRUE(pair) << error;
  const mode_t old_umask = ::umask(0);  // a careless umask must not widen the secret file
  const auto paths = writeKeyPair(*pair, dir.path / "keys", false, &error);
  ::umask(old_umask);
  ASSERT_TRUE(paths) << error;
  EXPECT_EQ(modeOf(paths->secret_file), 0600u);
  EXPECT_EQ(modeOf(paths->public_file), 0644u);
  const auto back = readKeyPair(paths->secret_file, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->key.name, "alice");
  EXPECT_EQ(back->key.role, LinkRole::kOperator);
  EXPECT_EQ(back->key.public_z85, pair->key.public_z85);
  EXPECT_EQ(back->secret_z85, pair->secret_z85);
  const auto pub = readPublicKey(paths->public_file, &error);
  ASSERT_TRUE(pub) << error;
  EXPECT_EQ(pub->public_z85, pair->key.public_z85);
  // The public file holds no secret.
  std::stringstream text;
  text << std::ifstream(paths->public_file).rdbuf();
  EXPECT_EQ(text.str().find(pair->secret_z85), std::string::npos);
  EXPECT_EQ(text.str().find("secret_key"), std::string::npos);
  EXPECT_FALSE(readKeyPair(paths->public_file, &error));  // 0644, and no secret in it
}

TEST(LinkKeyFiles, ASecretOthersMayReadIsRefusedWithThePathAndTheFix) {
  TempDir dir;
  std::string error;
  const auto pair = generateKeyPair("bob", LinkRole::kSupervisor, &error);
  const auto paths = writeKeyPair(*pair, dir.path, false, &error);
  ASSERT_TRUE(paths) << error;
  for (const mode_t mode : {0644, 0640, 0604}) {
    ::chmod(paths->secret_file.c_str(), mode);
    EXPECT_FALSE(readKeyPair(paths->secret_file, &error)) << std::oct << mode;
    EXPECT_NE(error.find(paths->secret_file.string()), std::string::npos) << error;
    EXPECT_NE(error.find("chmod 600 " + paths->secret_file.string()), std::string::npos) << error;
  }
  ::chmod(paths->secret_file.c_str(), 0400);
  EXPECT_TRUE(readKeyPair(paths->secret_file, &error)) << error;
}

TEST(LinkKeyFiles, AMixedUpPairAnExistingKeyAndBrokenFilesAreRefused) {
  TempDir dir;
  std::string error;
  auto a = generateKeyPair("carol", LinkRole::kViewer, &error);
  const auto b = generateKeyPair("dave", LinkRole::kViewer, &error);
  ASSERT_TRUE(writeKeyPair(*a, dir.path, false, &error)) << error;
  // Not replaced without being asked to.
  EXPECT_FALSE(writeKeyPair(*a, dir.path, false, &error));
  EXPECT_NE(error.find("exists"), std::string::npos) << error;
  EXPECT_NE(error.find("--force"), std::string::npos) << error;
  // A public key that is not the secret's own.
  a->key.public_z85 = b->key.public_z85;
  ASSERT_TRUE(writeKeyPair(*a, dir.path, true, &error)) << error;
  EXPECT_FALSE(readKeyPair(dir.path / "carol.secret", &error));
  EXPECT_NE(error.find("is not the one its secret_key makes"), std::string::npos) << error;
  // Not a key file; an unknown role; missing.
  std::ofstream(dir.path / "junk.pub") << "just: [text\n";
  EXPECT_FALSE(readPublicKey(dir.path / "junk.pub", &error));
  EXPECT_NE(error.find("junk.pub"), std::string::npos) << error;
  std::ofstream(dir.path / "eve.pub") << "name: eve\nrole: admin\npublic_key: \"" << b->key.public_z85 << "\"\n";
  EXPECT_FALSE(readPublicKey(dir.path / "eve.pub", &error));
  EXPECT_NE(error.find("role \"admin\" is not one of robot|operator|supervisor|viewer"), std::string::npos) << error;
  EXPECT_FALSE(readPublicKey(dir.path / "nobody.pub", &error));
  EXPECT_NE(error.find("nobody.pub"), std::string::npos) << error;
}

/// Runs `command` (stderr joined to stdout); the exit code.
int run(const std::string& command, std::string* output) {
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return -1;
  std::array<char, 4096> buf{};
  output->clear();
  while (const std::size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) output->append(buf.data(), n);
  const int status = ::pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(TelesphereKeys, GeneratesShowsAndRefusesWithTheReason) {
  TempDir dir;
  const std::string keys = TELESPHERE_BINARY_DIR "/bin/telesphere-keys";
  const std::string out = (dir.path / "robot-keys").string();
  std::string text;
  ASSERT_EQ(run(keys + " generate --role robot --name rig-pc --out " + out, &text), 0) << text;
  EXPECT_NE(text.find("rig-pc.pub"), std::string::npos) << text;
  EXPECT_EQ(modeOf(out + "/rig-pc.secret"), 0600u);
  std::string error;
  const auto pair = readKeyPair(out + "/rig-pc.secret", &error);
  ASSERT_TRUE(pair) << error;
  EXPECT_EQ(pair->key.role, LinkRole::kRobot);
  EXPECT_NE(text.find(pair->key.public_z85), std::string::npos) << text;

  EXPECT_EQ(run(keys + " generate --role robot --name rig-pc --out " + out, &text), 1);
  EXPECT_NE(text.find("exists"), std::string::npos) << text;
  EXPECT_EQ(run(keys + " generate --role robot --name rig-pc --out " + out + " --force", &text), 0) << text;
  EXPECT_EQ(run(keys + " generate --role admin --name x --out " + out, &text), 1);
  EXPECT_NE(text.find("robot|operator|supervisor|viewer"), std::string::npos) << text;

  EXPECT_EQ(run(keys + " show " + out + "/rig-pc.pub " + out + "/rig-pc.secret", &text), 0) << text;
  EXPECT_NE(text.find("rig-pc (robot)"), std::string::npos) << text;
  ::chmod((out + "/rig-pc.secret").c_str(), 0644);
  EXPECT_EQ(run(keys + " show " + out + "/rig-pc.secret", &text), 1);
  EXPECT_NE(text.find("chmod 600 " + out + "/rig-pc.secret"), std::string::npos) << text;
}

}  // namespace
}  // namespace telesphere::link::trust
