#include "services/viewer/static_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace haptex::viewer {
namespace {

namespace fs = std::filesystem;

void WriteFile(const fs::path& path, const std::string& content) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << content;
}

// <tmp>/site/{index.html, app.js, style.css, img/logo.png, data.json}, <tmp>/three/three.module.js,
// <tmp>/secret.txt outside both roots, and symlinks in the web root pointing in and out.
class StaticFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    base_ = fs::temp_directory_path() /
            ("haptex_static_files_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(base_);
    WriteFile(base_ / "site/index.html", "<html></html>");
    WriteFile(base_ / "site/app.js", "export {};");
    WriteFile(base_ / "site/style.css", "body{}");
    WriteFile(base_ / "site/img/logo.png", "PNG");
    WriteFile(base_ / "site/data.json", "{}");
    WriteFile(base_ / "site/notes.unknownext", "x");
    WriteFile(base_ / "three/three.module.js", "// three");
    WriteFile(base_ / "secret.txt", "secret");
    fs::create_directories(base_ / "site/folder.js");
    fs::create_symlink(base_ / "secret.txt", base_ / "site/escape.txt");
    fs::create_symlink(base_, base_ / "site/up");
    fs::create_symlink(base_ / "site/app.js", base_ / "site/alias.js");
    roots_ = {base_ / "site", base_ / "three"};
  }
  void TearDown() override { fs::remove_all(base_); }

  std::optional<StaticFile> Resolve(const std::string& target) { return ResolveStaticFile(roots_, target); }

  fs::path base_;
  StaticFileRoots roots_;
};

TEST_F(StaticFilesTest, ServesFilesOfTheWebRootWithTheirContentType) {
  const auto index = Resolve("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->path, fs::canonical(base_ / "site/index.html"));
  EXPECT_EQ(index->content_type, "text/html; charset=utf-8");
  EXPECT_EQ(Resolve("/index.html")->path, index->path);
  EXPECT_EQ(Resolve("/app.js")->content_type, "text/javascript; charset=utf-8");
  EXPECT_EQ(Resolve("/style.css")->content_type, "text/css; charset=utf-8");
  EXPECT_EQ(Resolve("/img/logo.png")->content_type, "image/png");
  EXPECT_EQ(Resolve("/data.json")->content_type, "application/json");
}

TEST_F(StaticFilesTest, ServesThreeFromItsOwnRoot) {
  const auto three = Resolve("/three/three.module.js");
  ASSERT_TRUE(three);
  EXPECT_EQ(three->path, fs::canonical(base_ / "three/three.module.js"));
  EXPECT_EQ(three->content_type, "text/javascript; charset=utf-8");
  EXPECT_FALSE(Resolve("/three/../secret.txt"));
  EXPECT_FALSE(Resolve("/three/"));
}

TEST_F(StaticFilesTest, IgnoresQueryAndFragmentAndDecodesEscapes) {
  EXPECT_TRUE(Resolve("/app.js?v=3"));
  EXPECT_TRUE(Resolve("/app.js#top"));
  EXPECT_TRUE(Resolve("/%61pp.js"));
  EXPECT_TRUE(Resolve("/img%2Flogo.png"));
}

TEST_F(StaticFilesTest, RefusesTraversal) {
  EXPECT_FALSE(Resolve("/../secret.txt"));
  EXPECT_FALSE(Resolve("/img/../../secret.txt"));
  EXPECT_FALSE(Resolve("/img/../index.html"));  // no ".." at all, even when it stays inside
  EXPECT_FALSE(Resolve("/%2e%2e/secret.txt"));
  EXPECT_FALSE(Resolve("/%2E%2E%2Fsecret.txt"));
  EXPECT_FALSE(Resolve("/img/%2e%2e/%2e%2e/secret.txt"));
  EXPECT_FALSE(Resolve("/./index.html"));
  EXPECT_FALSE(Resolve("/..%5csecret.txt"));
  EXPECT_FALSE(Resolve("/img\\..\\..\\secret.txt"));
}

TEST_F(StaticFilesTest, RefusesAbsolutePaths) {
  const std::string secret = (base_ / "secret.txt").string();
  EXPECT_FALSE(Resolve("/" + secret));  // "//tmp/..." has an empty segment
  EXPECT_FALSE(Resolve(secret.substr(1)));
  EXPECT_FALSE(Resolve("/%2f" + secret.substr(1)));
  EXPECT_FALSE(Resolve("http://host/index.html"));
  EXPECT_FALSE(Resolve(""));
}

TEST_F(StaticFilesTest, RefusesNulAndBadEscapes) {
  EXPECT_FALSE(Resolve("/index.html%00.png"));
  EXPECT_FALSE(Resolve(std::string("/index.html\0.png", 16)));
  EXPECT_FALSE(Resolve("/index.html%"));
  EXPECT_FALSE(Resolve("/index.html%2"));
  EXPECT_FALSE(Resolve("/index%zz.html"));
}

TEST_F(StaticFilesTest, FollowsSymlinksOnlyInsideTheRoot) {
  EXPECT_FALSE(Resolve("/escape.txt"));
  EXPECT_FALSE(Resolve("/up/secret.txt"));
  const auto alias = Resolve("/alias.js");
  ASSERT_TRUE(alias);
  EXPECT_EQ(alias->path, fs::canonical(base_ / "site/app.js"));
}

TEST_F(StaticFilesTest, RefusesMissingFilesFoldersAndUnknownTypes) {
  EXPECT_FALSE(Resolve("/missing.html"));
  EXPECT_FALSE(Resolve("/folder.js"));
  EXPECT_FALSE(Resolve("/img"));
  EXPECT_FALSE(Resolve("/notes.unknownext"));
  EXPECT_FALSE(Resolve("/img/"));
}

TEST_F(StaticFilesTest, AnEmptyRootServesNothing) {
  EXPECT_FALSE(ResolveStaticFile({"", ""}, "/"));
  EXPECT_FALSE(ResolveStaticFile({"", ""}, "/three/three.module.js"));
  EXPECT_FALSE(ResolveStaticFile({base_ / "site", ""}, "/three/three.module.js"));
}

TEST(PercentDecodeTest, DecodesAndRefusesMalformedEscapes) {
  EXPECT_EQ(PercentDecode("a%20b%2Fc"), "a b/c");
  EXPECT_EQ(PercentDecode("plain"), "plain");
  EXPECT_FALSE(PercentDecode("%"));
  EXPECT_FALSE(PercentDecode("%4"));
  EXPECT_FALSE(PercentDecode("%g0"));
  EXPECT_FALSE(PercentDecode("%00"));
}

TEST(ContentTypeOfTest, KnowsTheViewersTypes) {
  EXPECT_EQ(ContentTypeOf("a.html"), "text/html; charset=utf-8");
  EXPECT_EQ(ContentTypeOf("a.mjs"), "text/javascript; charset=utf-8");
  EXPECT_FALSE(ContentTypeOf("a.exe"));
  EXPECT_FALSE(ContentTypeOf("Makefile"));
}

}  // namespace
}  // namespace haptex::viewer
