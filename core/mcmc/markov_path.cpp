#include "mcmc/markov_path.h"

#include "camera.h"
#include "path/path.h"
#include "path/short_edge_damping.h"
#include "render_scene.h"

namespace partita {

bool evaluatePath(const RenderScene& scene, const Camera& camera, MarkovPath& x) {
    x.fStar = 0;
    x.f = Rgb(0.0f);
    if (x.vertices.size() < 2) return false;
    std::optional<Vec2f> raster = pathRaster(camera, x.vertices);
    if (!raster || !camera.inImportanceSupport(*raster)) return false;
    Rgb f = pathContribution(scene, camera, x.vertices, DiracVertices::Coefficient);
    // The chains' target: lum(f) damped on very short edges (short_edge_damping.h).
    ShortEdgeDamping damping(scene.shortEdge());
    for (const PathVertex& v : x.vertices) damping.add(v.p);
    float fStar = luminance(f) * damping.factor();
    if (!(fStar > 0) || !isFinite(f)) return false;
    x.f = f;
    x.fStar = fStar;
    x.raster = *raster;
    x.type = pathType(x.vertices);
    return true;
}

}  // namespace partita
