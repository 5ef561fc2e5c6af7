#include "guide/guided_choice.h"

namespace partita {

int chooseCandidate(const CandidateWeights& candidates, double u) {
    if (!(candidates.sum > 0)) return -1;
    double target = u * candidates.sum, running = 0;
    int last = -1;
    for (size_t k = 0; k < candidates.weights.size(); ++k) {
        float w = candidates.weights[k];
        if (!(w > 0)) continue;
        last = int(k);
        running += double(w);
        if (target < running) return int(k);
    }
    return last;  // u within rounding of 1
}

double candidateProbability(const std::vector<PixelOffset>& delta, const CandidateWeights& atP,
                            int px, int py, int qx, int qy) {
    if (!(atP.sum > 0)) return 0;
    double weight = 0;
    for (size_t k = 0; k < delta.size(); ++k)
        if (px + delta[k].dx == qx && py + delta[k].dy == qy) weight += double(atP.weights[k]);
    return weight / atP.sum;
}

double guidedProposalRatio(const std::vector<PixelOffset>& delta, const CandidateWeights& atP,
                           const CandidateWeights& atQ, int px, int py, int qx, int qy) {
    double forward = candidateProbability(delta, atP, px, py, qx, qy);
    double reverse = candidateProbability(delta, atQ, qx, qy, px, py);
    return forward > 0 ? reverse / forward : 0;
}

}  // namespace partita
