// In-process A/B of the queries on the coherent-motion scenes (run.sh … coherent builds it): per scene and method,
// `rounds` alternations of the old and the new side; prints the medians, the median and range of the
// per-alternation new/old ratios, whether every result is the same on both sides, and each side's median
// cold-distance / warm-distance ratio (the "≥ 5× cheaper than cold GJK").
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>
double coh_old(int, int, int, double*);
double coh_new(int, int, int, double*);
int main(int argc, char** argv) {
    const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 7;
    const int passes = argc > 2 ? std::max(1, std::atoi(argv[2])) : 1;
    const char* scene_names[3] = {"separated", "near-touching", "in-and-out"};
    const char* method_names[6] = {"cold distance", "warm distance",    "cold boolean",
                                   "warm boolean",  "separating plane", "closest features"};
    const int reps[6] = {2, 10, 10, 20, 20, 10};  // passes per measurement, times `passes`: ~5-20 ms each
    for (int sc = 0; sc < 3; ++sc) {
        double med[2][6];
        for (int m = 0; m < 6; ++m) {
            std::vector<double> to, tn, rt;
            double so = 0, sn = 0;
            for (int r = 0; r < rounds; ++r) {
                to.push_back(coh_old(sc, m, reps[m] * passes, &so));
                tn.push_back(coh_new(sc, m, reps[m] * passes, &sn));
                rt.push_back(tn.back() / to.back());
            }
            std::sort(to.begin(), to.end());
            std::sort(tn.begin(), tn.end());
            std::sort(rt.begin(), rt.end());
            med[0][m] = to[std::size_t(rounds / 2)];
            med[1][m] = tn[std::size_t(rounds / 2)];
            std::printf("%-13s %-13s old %7.1f new %7.1f ns (median of %d)  new/old median %.3f [%.3f..%.3f]  %s\n",
                        scene_names[sc], method_names[m], med[0][m], med[1][m], rounds, rt[std::size_t(rounds / 2)],
                        rt.front(), rt.back(), so == sn ? "same results" : "RESULTS DIFFER");
        }
        for (int m = 1; m < 6; ++m)
            std::printf("%-13s cold distance / %s: old %.2f new %.2f\n", scene_names[sc], method_names[m],
                        med[0][0] / med[0][m], med[1][0] / med[1][m]);
    }
}
