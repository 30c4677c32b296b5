// The outputs of one command land together or not at all (io/files.h), and the limits every
// option and allocation is held to (pipeline/option_limits.h, model/memory_budget.h).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "csgfit/model/bitmap.h"
#include "csgfit/model/memory_budget.h"
#include "csgfit/pipeline/option_limits.h"
#include "scratch_dir.h"

namespace fs = std::filesystem;

namespace csgfit {
namespace {

class OutputBatchTest : public testing::ScratchDirTest {
 protected:
  // The folder's entries, hidden temporary files included.
  std::size_t entries() const {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir_)) n += e.exists() ? 1 : 0;
    return n;
  }
};

TEST_F(OutputBatchTest, ABatchThatIsNotCommittedLeavesNothing) {
  {
    OutputBatch batch;
    write_file_atomic(dir_ + "/a.scad", "cube(1);\n");
    write_file_atomic(dir_ + "/b.png", "png");
    EXPECT_FALSE(fs::exists(dir_ + "/a.scad"));  // waiting under a temporary name
    EXPECT_EQ(entries(), 2u);
  }  // the command failed before its commit
  EXPECT_EQ(entries(), 0u);
}

TEST_F(OutputBatchTest, ACommittedBatchPutsEveryFileInPlace) {
  OutputBatch batch;
  write_file_atomic(dir_ + "/a.scad", "cube(1);\n");
  const std::string temp = make_temp_beside(dir_ + "/c.step");
  EXPECT_EQ(fs::path(temp).extension(), ".step");  // writers that pick formats by name
  publish_file(temp, dir_ + "/c.step");
  batch.commit();
  EXPECT_TRUE(fs::exists(dir_ + "/a.scad"));
  EXPECT_TRUE(fs::exists(dir_ + "/c.step"));
  EXPECT_EQ(entries(), 2u);
}

TEST_F(OutputBatchTest, AWriteThatFailsTakesTheEarlierOnesWithIt) {
  {
    OutputBatch batch;
    write_file_atomic(dir_ + "/a.json", "{}");
    EXPECT_THROW(write_file_atomic(dir_ + "/sub/b.png", "png"), InputError);  // no such folder
  }  // the command stops there, without a commit
  EXPECT_EQ(entries(), 0u);
}

TEST_F(OutputBatchTest, ACommitThatFailsKeepsNone) {
  {
    OutputBatch batch;
    write_file_atomic(dir_ + "/a.json", "{}");
    write_file_atomic(dir_ + "/b.png", "png");
    fs::create_directory(dir_ + "/b.png");  // the second rename now fails
    fs::create_directory(dir_ + "/b.png/x");  // (a non-empty folder, so rename cannot replace it)
    EXPECT_THROW(batch.commit(), InputError);
  }
  EXPECT_FALSE(fs::exists(dir_ + "/a.json"));
  EXPECT_EQ(entries(), 1u);  // only the folder made above
}

TEST_F(OutputBatchTest, WithoutABatchWritesLandAtOnce) {
  write_file_atomic(dir_ + "/a.scad", "cube(1);\n");
  EXPECT_TRUE(fs::exists(dir_ + "/a.scad"));
  EXPECT_EQ(entries(), 1u);
}

TEST(OptionLimits, EveryRuleRefusesNanInfinityAndItsBounds) {
  for (const NumberRule* rule :
       {&option_rules::time, &option_rules::threads, &option_rules::k, &option_rules::scale,
        &option_rules::thickness, &option_rules::fn, &option_rules::focal_length}) {
    EXPECT_FALSE(rule_violation(*rule, std::nan("")).empty()) << rule->what;
    EXPECT_FALSE(rule_violation(*rule, std::numeric_limits<double>::infinity()).empty());
    EXPECT_FALSE(rule_violation(*rule, rule->hi * 2 + 1).empty()) << rule->what;
    EXPECT_TRUE(rule_violation(*rule, rule->hi).empty()) << rule->what;
  }
  EXPECT_FALSE(rule_violation(option_rules::time, 0).empty());
  EXPECT_FALSE(rule_violation(option_rules::threads, 1.5).empty());
  EXPECT_EQ(rule_violation(option_rules::threads, 2147483647.0),
            "must be a thread count (0 = all cores), an integer in 0 .. 256, not 2147483647");
}

TEST(OptionLimits, SeedsAndMemorySizesAreReadExactly) {
  EXPECT_EQ(parse_seed("--seed", "18446744073709551615"), 18446744073709551615ULL);
  EXPECT_THROW(parse_seed("--seed", "-1"), InputError);
  EXPECT_THROW(parse_seed("--seed", "18446744073709551616"), InputError);
  EXPECT_THROW(parse_seed("--seed", "1e3"), InputError);
  EXPECT_EQ(parse_memory_size("--max-memory", "4G"), 4.0 * (1 << 30));
  EXPECT_EQ(parse_memory_size("--max-memory", "512MB"), 512.0 * (1 << 20));
  EXPECT_THROW(parse_memory_size("--max-memory", "1K"), InputError);
  EXPECT_THROW(parse_memory_size("--max-memory", "lots"), InputError);
}

TEST(MemoryBudget, ALargeRasterIsRefusedBeforeItIsAllocated) {
  set_memory_budget(std::size_t{32} << 20);
  EXPECT_THROW(Bitmap(60000, 60000), InputError);  // 450 MB of bits
  EXPECT_NO_THROW(Bitmap(1000, 1000));
  set_memory_budget(0);
  EXPECT_EQ(memory_budget(), default_memory_budget());
}

TEST(PrintableMessage, KeepsOneLineOfTextThatCannotRecolourATerminal) {
  EXPECT_EQ(printable_message("bad \x1b[31mred\x1b[0m\n"), "bad ?[31mred?[0m?");
  EXPECT_EQ(printable_message("Zeichnung_\xc3\xbc.png"), "Zeichnung_\xc3\xbc.png");  // UTF-8 stays
  EXPECT_EQ(printable_message("\xff\xfe" "a"), "??a");                             // invalid bytes
  EXPECT_EQ(printable_message("\xe2\x80\xae" "evil"), "???evil");  // right-to-left override
  EXPECT_EQ(printable_message(std::string(5000, 'x')).size(), 403u);
  EXPECT_EQ(std::string(InputError("a\tb").what()), "a?b");
}

}  // namespace
}  // namespace csgfit
