// partita compare: the numbers. An image against itself has RMSE 0; a constant offset c on every
// channel has RMSE c and relMSE mean(c^2 / (r^2 + 1e-2)).
#include "cli_test_util.h"
#include "image_io.h"

namespace partita::test {
namespace {

namespace fs = std::filesystem;

LayeredImage pattern(float offset) {
    LayeredImage img;
    const int w = 8, h = 6;
    Image a(w, h), b(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            a.set(x, y, {0.1f * x + offset, 0.05f * y + offset, 0.3f + offset});
            b.set(x, y, {0.02f * (x + y) + offset, 0.5f + offset, 0.01f * x * y + offset});
        }
    img.combined = Image(w, h);
    for (size_t i = 0; i < img.combined.rgb.size(); ++i)
        img.combined.rgb[i] = a.rgb[i] + b.rgb[i] - offset;  // the sum of the un-offset layers + c
    img.layers = {{"LDE", a}, {"LDDE", b}};
    return img;
}

double num(const std::string& s) { return std::stod(s); }

TEST(CliCompare, IdentityIsZeroAndOffsetGivesExpectedError) {
    TempDir dir;
    const float c = 0.25f;
    const LayeredImage ref = pattern(0), shifted = pattern(c);
    writeExr(dir / "ref.exr", ref);
    writeExr(dir / "same.exr", ref);
    writeExr(dir / "shifted.exr", shifted);

    RunResult r = partita({"compare", (dir / "same.exr").string(), (dir / "shifted.exr").string(),
                           "--reference", (dir / "ref.exr").string()});
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    auto rows = lines(r.out);
    ASSERT_EQ(rows.size(), 3u) << r.describe();
    EXPECT_EQ(words(rows[0]), (std::vector<std::string>{"image", "rmse", "relmse"}));
    auto same = words(rows[1]), off = words(rows[2]);
    EXPECT_EQ(num(same[1]), 0.0);
    EXPECT_EQ(num(same[2]), 0.0);
    EXPECT_NEAR(num(off[1]), c, 1e-6);
    double rel = 0;
    for (float v : ref.combined.rgb) rel += double(c) * c / (double(v) * v + 1e-2);
    rel /= double(ref.combined.rgb.size());
    EXPECT_NEAR(num(off[2]), rel, 1e-5 * rel);

    RunResult layers = partita({"compare", (dir / "shifted.exr").string(), "--reference",
                                (dir / "ref.exr").string(), "--layers"});
    ASSERT_EQ(layers.exitCode, 0) << layers.describe();
    rows = lines(layers.out);
    ASSERT_EQ(rows.size(), 4u) << layers.describe();
    EXPECT_EQ(words(rows[0]), (std::vector<std::string>{"image", "layer", "rmse", "relmse"}));
    EXPECT_EQ(words(rows[1])[1], "combined");
    EXPECT_EQ(words(rows[2])[1], "LDE");
    EXPECT_EQ(words(rows[3])[1], "LDDE");
    for (int i = 1; i <= 3; ++i) EXPECT_NEAR(num(words(rows[i])[2]), c, 1e-6) << rows[i];
}

TEST(CliCompare, SizeMismatchAndMissingFilesFailInOneLine) {
    TempDir dir;
    writeExr(dir / "ref.exr", pattern(0));
    LayeredImage small;
    small.combined = Image(4, 4);
    writeExr(dir / "small.exr", small);
    expectOneLineError(partita({"compare", (dir / "small.exr").string(), "--reference",
                                (dir / "ref.exr").string()}),
                       "4x4");
    expectOneLineError(partita({"compare", (dir / "nope.exr").string(), "--reference",
                                (dir / "ref.exr").string()}),
                       "nope.exr");
    expectOneLineError(partita({"compare", (dir / "ref.exr").string()}), "--reference");
}

}  // namespace
}  // namespace partita::test
