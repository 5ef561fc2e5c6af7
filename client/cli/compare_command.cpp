// partita compare IMAGE... --reference REF.exr [--layers]
// RMSE and relMSE (core/image_metrics.h) of each image's combined layer against the reference's,
// and with --layers also of every layer the image and the reference have in common. Needs no
// server.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/image_files.h"
#include "cli/table.h"

namespace partita::cli {

namespace {

struct CompareArgs {
    std::vector<std::string> images;
    std::string reference;
    bool layers = false;
};

int runCompare(const CompareArgs& a) {
    const LayeredImage reference = readResultExr(a.reference);
    Table table(a.layers ? std::vector<std::string>{"image", "layer", "rmse", "relmse"}
                         : std::vector<std::string>{"image", "rmse", "relmse"});
    for (const auto& path : a.images) {
        const LayeredImage image = readResultExr(path);
        ErrorMetrics m;
        try {
            m = imageError(image.combined, reference.combined);
        } catch (const CliError& e) {
            throw CliError("'" + path + "': " + e.what());
        }
        if (!a.layers) {
            table.addRow({path, formatNumber(m.rmse), formatNumber(m.relMse)});
            continue;
        }
        table.addRow({path, "combined", formatNumber(m.rmse), formatNumber(m.relMse)});
        for (const auto& layer : image.layers) {
            const Image* ref = reference.layer(layer.name);
            if (!ref) continue;
            ErrorMetrics lm = imageError(layer.image, *ref);
            table.addRow({path, layer.name, formatNumber(lm.rmse), formatNumber(lm.relMse)});
        }
    }
    table.print(stdout);
    return 0;
}

}  // namespace

Command addCompareCommand(CLI::App& app, const GlobalOptions&) {
    auto args = std::make_shared<CompareArgs>();
    CLI::App* sub = app.add_subcommand("compare", "error of images against a reference EXR");
    sub->add_option("images", args->images, "EXR files to compare")->required();
    sub->add_option("--reference", args->reference, "the reference EXR")->required();
    sub->add_flag("--layers", args->layers, "also compare every layer both files have");
    return {sub, [args] { return runCompare(*args); }};
}

}  // namespace partita::cli
