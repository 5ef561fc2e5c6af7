// Tests of the error per partition of a partitioned render (tools/eval/partition_error.h), the
// figures `partita-eval quality` reports for `partitioned`.
#include <gtest/gtest.h>

#include <cmath>

#include "eval/partition_error.h"

namespace partita::eval {
namespace {

Image filled(float v) {
    Image image(2, 1);
    for (float& x : image.rgb) x = v;
    return image;
}

/// A reference with three types whose layers sum to the combined image: LDE 1, LSDE 2, LDDE 4.
LayeredImage reference() {
    LayeredImage ref;
    ref.combined = filled(7);
    ref.layers = {{"LDE", filled(1)}, {"LSDE", filled(2)}, {"LDDE", filled(4)}};
    return ref;
}

TEST(PartitionError, LabelsComeInPartitionOrderUntilTheFirstGap) {
    std::map<std::string, std::string> labels = {{"partition_0_type", "LSDE"},
                                                 {"partition_1_type", "complement"},
                                                 {"partition_3_type", "LDE"},
                                                 {"prepass", "pt"}};
    EXPECT_EQ(partitionLabels(labels), (std::vector<std::string>{"LSDE", "complement"}));
    EXPECT_TRUE(partitionLabels({{"prepass", "pt"}}).empty());
}

TEST(PartitionError, TheComplementIsComparedWithTheCombinedReferenceMinusTheTypes) {
    // Partitions LSDE and the complement (LDE + LDDE = 5 in the reference).
    LayeredImage render;
    render.layers = {{"LSDE", filled(2.5f)}, {"complement", filled(4)}};
    render.combined = filled(6.5f);
    auto e = partitionErrors(render, {"LSDE", "complement"}, reference());
    ASSERT_EQ(e.size(), 2u);
    EXPECT_EQ(e[0].layer, "LSDE");
    EXPECT_TRUE(e[0].inReference);
    EXPECT_NEAR(e[0].rmse, 0.5, 1e-12);
    EXPECT_NEAR(e[0].squaredError, 6 * 0.25, 1e-12);  // 2 pixels x 3 values
    EXPECT_NEAR(e[0].relMse, 0.25 / (4 + 1e-2), 1e-12);
    EXPECT_EQ(e[1].layer, "complement");
    EXPECT_NEAR(e[1].rmse, 1.0, 1e-12);  // 4 against 7 - 2
    EXPECT_NEAR(e[1].squaredError, 6.0, 1e-12);
    // The combined error is 0.5 per value: squared 1.5; the errors of the two partitions have
    // opposite signs, so the shares (1 and 4) sum to more than 1 (the cross term is -2 x 0.5).
    EXPECT_NEAR(e[0].share, 1.0, 1e-12);
    EXPECT_NEAR(e[1].share, 4.0, 1e-12);
}

TEST(PartitionError, AClassIsComparedWithTheSumOfItsTypes) {
    // Partitions LD+E (LDE + LDDE = 5 in the reference) and the complement (LSDE = 2).
    LayeredImage render;
    render.layers = {{"LD+E", filled(5.5f)}, {"complement", filled(2)}};
    render.combined = filled(7.5f);
    auto e = partitionErrors(render, {"LD+E", "complement"}, reference());
    EXPECT_TRUE(e[0].inReference);
    EXPECT_NEAR(e[0].rmse, 0.5, 1e-12);
    EXPECT_TRUE(e[1].inReference);
    EXPECT_NEAR(e[1].rmse, 0.0, 1e-12);
    // With an "other" in the reference the class may lie partly in it: marked.
    LayeredImage ref = reference();
    ref.layers.push_back({"other", filled(0)});
    e = partitionErrors(render, {"LD+E", "complement"}, ref);
    EXPECT_FALSE(e[0].inReference);
    EXPECT_FALSE(e[1].inReference);
}

TEST(PartitionError, TheDirectLightIsItsTypesAndAClassBesideItHoldsNoneOfThem) {
    // Partitions direct (LDE, LSE: the direct-light types), LD+E (LDDE only: LDE is direct) and
    // the complement (LSDE), as partitioned renders them with the direct light apart.
    LayeredImage ref = reference();
    ref.layers.push_back({"LSE", filled(8)});
    ref.combined = filled(15);
    LayeredImage render;
    render.layers = {{"direct", filled(9.5f)}, {"LD+E", filled(4)}, {"complement", filled(2)}};
    render.combined = filled(15.5f);
    auto e = partitionErrors(render, {"direct", "LD+E", "complement"}, ref);
    ASSERT_EQ(e.size(), 3u);
    EXPECT_TRUE(e[0].inReference);
    EXPECT_NEAR(e[0].rmse, 0.5, 1e-12);  // 9.5 against LDE + LSE = 9
    EXPECT_NEAR(e[1].rmse, 0.0, 1e-12);  // 4 against LDDE, not LDE + LDDE
    EXPECT_NEAR(e[2].rmse, 0.0, 1e-12);  // 2 against 15 - 9 - 4
    // A render without partition layers (mlt) split the same way.
    bool complete = false;
    Image direct = partitionLayer(ref, "direct", true, complete);
    EXPECT_TRUE(complete);
    EXPECT_EQ(direct.rgb[0], 9.0f);
    EXPECT_EQ(partitionLayer(ref, "LD+E", true, complete).rgb[0], 4.0f);
    EXPECT_EQ(partitionLayer(ref, "LD+E", false, complete).rgb[0], 5.0f);
}

TEST(PartitionError, ATypeTheReferenceLacksIsComparedWithBlack) {
    LayeredImage render;
    render.layers = {{"LSSDE", filled(0.5f)}, {"complement", filled(7)}};
    render.combined = filled(7.5f);
    auto e = partitionErrors(render, {"LSSDE", "complement"}, reference());
    EXPECT_FALSE(e[0].inReference);
    EXPECT_NEAR(e[0].rmse, 0.5, 1e-12);
    EXPECT_TRUE(e[1].inReference);
    EXPECT_NEAR(e[1].rmse, 0.0, 1e-12);  // the complement's reference is all of the combined
    EXPECT_NEAR(e[0].share, 1.0, 1e-12);
}

TEST(PartitionError, TheComplementOfAReferenceThatMayHideATypeInOtherIsMarked) {
    LayeredImage ref = reference();
    ref.layers.back().name = "other";  // LDDE merged into "other": LSSDE could be there too
    LayeredImage render;
    render.layers = {{"LSSDE", filled(0.5f)}, {"complement", filled(7)}};
    render.combined = filled(7.5f);
    auto e = partitionErrors(render, {"LSSDE", "complement"}, ref);
    EXPECT_FALSE(e[0].inReference);
    EXPECT_FALSE(e[1].inReference);
    render.layers = {{"LDE", filled(1)}, {"complement", filled(6)}};
    render.combined = filled(7);
    e = partitionErrors(render, {"LDE", "complement"}, ref);
    EXPECT_TRUE(e[0].inReference);
    EXPECT_TRUE(e[1].inReference);  // its types are all there: "other" is in the complement
    EXPECT_NEAR(e[1].rmse, 0.0, 1e-12);
}

TEST(PartitionError, AMissingLayerOrAnotherSizeIsAnError) {
    LayeredImage render;
    render.combined = filled(7);
    render.layers = {{"LDE", filled(1)}};
    EXPECT_THROW(partitionErrors(render, {"LDE", "complement"}, reference()),
                 std::invalid_argument);
    render.layers = {{"LDE", Image(3, 1)}};
    EXPECT_THROW(partitionErrors(render, {"LDE"}, reference()), std::invalid_argument);
}

}  // namespace
}  // namespace partita::eval
