// Errors that quote bad input stay one printable line: a corrupt file's newline, escape
// sequence or binary bytes must not reach the terminal raw, and a huge value is cut.
#include <gtest/gtest.h>

#include <string>

#include "room_reverb/common/error.h"
#include "test_files.h"
#include "tool_run.h"

namespace room_reverb::test {
namespace {

using core::InputError;
using core::printableLine;

bool hasControlCharacter(const std::string& s) {
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) return true;
  }
  return false;
}

TEST(PrintableLine, EscapesControlCharactersAndKeepsText) {
  EXPECT_EQ(printableLine("a\nb\tc\rd"), "a\\nb\\tc\\rd");
  EXPECT_EQ(printableLine(std::string("x\x1b[31my\x7f", 8)), "x\\x1b[31my\\x7f");
  EXPECT_EQ(printableLine(std::string("nul\0end", 7)), "nul\\x00end");
  EXPECT_EQ(printableLine("plain text: 1.5 m"), "plain text: 1.5 m");
}

TEST(PrintableLine, KeepsValidUtf8AndEscapesInvalidBytes) {
  EXPECT_EQ(printableLine("Raum/Bühne/测试.wav"), "Raum/Bühne/测试.wav");
  EXPECT_EQ(printableLine("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(printableLine("a\xc3"), "a\\xc3");          // truncated sequence
  EXPECT_EQ(printableLine("\xc0\xaf"), "\\xc0\\xaf");   // overlong '/'
  EXPECT_EQ(printableLine("\xed\xa0\x80"), "\\xed\\xa0\\x80");  // a UTF-16 surrogate
}

TEST(PrintableLine, CutsLongTextAndSaysHowMuch) {
  const std::string line = printableLine(std::string(1000, 'v'), 400);
  EXPECT_EQ(line, std::string(400, 'v') + "... (600 more bytes)");
  // Escapes count towards the cap: 200 newlines give 400 printed bytes.
  EXPECT_EQ(printableLine(std::string(300, '\n'), 400).substr(400), "... (100 more bytes)");
}

TEST(PrintableLine, InputErrorStoresThePrintableForm) {
  const InputError e(std::string("value '12\nab\x1b[31m' is not a number"));
  EXPECT_FALSE(hasControlCharacter(e.what()));
  EXPECT_EQ(std::string(e.what()), "value '12\\nab\\x1b[31m' is not a number");
}

// The case a user met: a corrupt RSAO YAML whose value holds a newline and an escape
// sequence made `render` print two lines carrying the raw bytes.
TEST(PrintableLine, RenderWithACorruptRsaoPrintsOneLine) {
  const std::string yaml =
      writeFile("corrupt_rsao.yaml", "reflections:\n  - {time_of_arrival_s: \"12\\nab\x1b[31mc\", level: 1}\n");
  const std::string source = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/dry/singing_anechoic.wav";
  const ToolRun run = runTool("render --source " + source + " --rsao " + yaml + " --out " + tempPath("never.wav").string());
  expectOneLineError(run, "time_of_arrival_s: '12\\nab\\x1b[31mc' is not a number");
  EXPECT_FALSE(hasControlCharacter(run.err.substr(0, run.err.size() - 1)));
}

TEST(PrintableLine, HugeUnknownSubcommandIsCut) {
  const ToolRun run = runTool(std::string(5000, 'z'));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_LT(run.err.size(), 300u) << run.err.size();
  EXPECT_NE(run.err.find("more bytes"), std::string::npos);
}

}  // namespace
}  // namespace room_reverb::test
