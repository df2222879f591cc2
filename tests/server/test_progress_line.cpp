// The runner's progress lines as the server reads them (server/progress_line.hpp).
// Cases the fuzz target fuzz_progress_line found: a cut inside a character
// left invalid UTF-8 in every job's JSON; negative or absurd numbers were
// kept as ETAs and rates.
#include "progress_line.hpp"

#include "api/progress_line.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

using namespace wiredem::server;

TEST(ProgressLine, ReadsTheFieldsALineGives)
{
    const auto p = parse_progress_line(R"({"stage":"test 2/3","progress":0.41,"eta_s":812.5,"message":"m","body_steps_per_second":2.5e6})");
    ASSERT_TRUE(p);
    EXPECT_EQ(p->stage, "test 2/3");
    EXPECT_EQ(p->progress, 0.41);
    EXPECT_TRUE(p->has_eta);
    EXPECT_EQ(p->eta_s, 812.5);
    EXPECT_EQ(p->message, "m");
    EXPECT_EQ(p->body_steps_per_second, 2.5e6);
    LiveProgress live;
    apply_progress_line(*p, live);
    EXPECT_EQ(live.state, JobState::running);
    EXPECT_EQ(live.eta_s, 812.5);
}

TEST(ProgressLine, OtherOutputIsNotAProgressLine)
{
    EXPECT_FALSE(parse_progress_line("pouring grains..."));
    EXPECT_FALSE(parse_progress_line("[1, 2]"));
    EXPECT_FALSE(parse_progress_line(R"({"stage": )"));
}

TEST(ProgressLine, ALongStageIsCutBeforeTheCharacterItWouldSplit)
{
    // 63 ASCII bytes, then "é" (two bytes) across the 64-byte limit: the cut
    // at 64 bytes left its lead byte alone, invalid UTF-8 in the job's JSON.
    const std::string stage = std::string(63, 'a') + "\xc3\xa9" + "tail";
    const auto p = parse_progress_line(R"({"stage":")" + stage + R"("})");
    ASSERT_TRUE(p && p->stage);
    EXPECT_EQ(*p->stage, std::string(63, 'a'));

    // A three-byte character (U+0807) across the message's 512-byte limit.
    const std::string message = std::string(511, 'm') + "\xe0\xa0\x87";
    const auto q = parse_progress_line(R"({"message":")" + message + R"("})");
    ASSERT_TRUE(q && q->message);
    EXPECT_EQ(*q->message, std::string(511, 'm'));
    // A character that ends at the limit is kept whole.
    const std::string exact = std::string(510, 'm') + "\xc3\xa9";
    const auto r = parse_progress_line(R"({"message":")" + exact + R"("})");
    ASSERT_TRUE(r && r->message);
    EXPECT_EQ(*r->message, exact);
}

TEST(ProgressLine, UnusableNumbersAreNotKept)
{
    const auto p = parse_progress_line(R"({"progress":-3,"eta_s":-5,"body_steps_per_second":0})");
    ASSERT_TRUE(p);
    EXPECT_EQ(p->progress, 0.0);  // clamped to [0, 1]
    EXPECT_TRUE(p->has_eta);      // the line gives an ETA, but no usable one
    EXPECT_FALSE(p->eta_s);
    EXPECT_FALSE(p->body_steps_per_second);

    LiveProgress live;
    live.eta_s = 60.0;
    apply_progress_line(*p, live);
    EXPECT_FALSE(live.eta_s);  // the earlier estimate is withdrawn, not kept stale
}

TEST(ProgressLine, AProgressThatIsNotANumberIsNotKept)
{
    // fuzz_progress_line found it: Boost.JSON reads 0e3006 as NaN, and clamp keeps a NaN.
    for (const char* line : {R"({"progress":0e3006})", R"({"progress":1e400})"}) {
        const auto p = parse_progress_line(line);
        ASSERT_TRUE(p) << line;
        EXPECT_FALSE(p->progress) << line;
    }
}

// The runner contract of docs/api.md names the keys and stages of
// api/progress_line.hpp, every one and no other; a line with every key is
// read whole, and each stage but the first makes a preparing job running.
TEST(ProgressLine, TheContractInTheDocsNamesTheKeysAndStagesOfTheOneList)
{
    namespace key = wiredem::api::progress_line;
    std::ifstream in(std::string(WIREDEM_SOURCE_DIR) + "/docs/api.md");
    ASSERT_TRUE(in) << "docs/api.md not found";
    std::ostringstream text;
    text << in.rdbuf();
    const std::string doc = text.str();
    const std::size_t from = doc.find("prints progress on stdout, one JSON object per line");
    ASSERT_NE(from, std::string::npos) << "docs/api.md: the runner contract's progress line";
    const std::string contract = doc.substr(from, doc.find("Other lines", from) - from);
    std::set<std::string> documented;
    const std::regex quoted("\"([a-z_]+)\"");
    for (auto it = std::sregex_iterator(contract.begin(), contract.end(), quoted); it != std::sregex_iterator(); ++it)
        documented.insert((*it)[1].str());
    std::set<std::string> listed(key::keys.begin(), key::keys.end());
    listed.insert(key::stages.begin(), key::stages.end());
    EXPECT_EQ(documented, listed) << "docs/api.md's runner contract and api/progress_line.hpp differ";

    const auto p = parse_progress_line(std::string("{\"") + key::stage + "\":\"" + key::testing + "\",\"" + key::progress
        + "\":0.5,\"" + key::eta_s + "\":3,\"" + key::message + "\":\"m\",\"" + key::body_steps_per_second + "\":7}");
    ASSERT_TRUE(p);
    EXPECT_EQ(p->stage, key::testing);
    EXPECT_EQ(p->progress, 0.5);
    EXPECT_EQ(p->eta_s, 3.0);
    EXPECT_EQ(p->message, "m");
    EXPECT_EQ(p->body_steps_per_second, 7.0);
    for (const std::string_view stage : key::stages) {
        LiveProgress live;
        ProgressLine line;
        line.stage = std::string(stage);
        apply_progress_line(line, live);
        EXPECT_EQ(live.state, stage == key::preparing ? JobState::preparing : JobState::running) << stage;
    }
}
