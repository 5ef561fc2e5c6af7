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

double guidedProposalRatio(const CandidateWeights& atP, const CandidateWeights& atQ, int k,
                           int back) {
    double forward = atP.sum > 0 ? double(atP.weights[size_t(k)]) / atP.sum : 0;
    double reverse = atQ.sum > 0 ? double(atQ.weights[size_t(back)]) / atQ.sum : 0;
    return forward > 0 ? reverse / forward : 0;
}

}  // namespace partita
