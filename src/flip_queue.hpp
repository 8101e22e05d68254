#pragma once
// The order of Lawson's flips (internal, not installed).

#include <bit>
#include <cstdint>
#include <queue>
#include <vector>

namespace sdmesh::detail {

// Candidate edges for Lawson's flips: last in, first out, so that the edges a flip pushes are
// tested next, while their faces are in cache; after longest_first(), by decreasing length.
// Last in, first out, the flips of a plane triangulated as a fan of n long faces from one rim
// vertex (CAD exporters make such caps) kept making new fans: about n²/13 flips, and a fan of
// 8,000 faces ran into the flip budgets. Longest first, each flip cuts the fan in two and n - 3
// flips make it Delaunay, but on the skull the intrinsic flips ran 4 times slower, jumping
// about the mesh. So the loops go longest first only once their flips outnumber the edges
// several times (kFlipsPerEdgeBeforeLongestFirst), which no corpus mesh reaches.
class FlipQueue {
public:
    // `length(e)` is called only once the queue goes longest first.
    template <class Length>
    void push(int e, Length&& length) {
        if (longest_first_)
            heap_.push(entry(length(e), e));
        else
            stack_.push_back(e);
    }
    // \pre not empty
    int pop() {
        if (!longest_first_) {
            const int e = stack_.back();
            stack_.pop_back();
            return e;
        }
        const int e = static_cast<int>(heap_.top() & 0xffffffffu);
        heap_.pop();
        return e;
    }
    // The edges `pop` returns next, in order (last in, first out only).
    const std::vector<int>& stack() const { return stack_; }
    bool empty() const { return stack_.empty() && heap_.empty(); }
    std::size_t size() const { return stack_.size() + heap_.size(); }

    // From now on, longest first (idempotent).
    template <class Length>
    void longest_first(Length&& length) {
        if (longest_first_) return;
        std::vector<std::uint64_t> entries;
        entries.reserve(stack_.size());
        for (const int e : stack_) entries.push_back(entry(length(e), e));
        heap_ = std::priority_queue<std::uint64_t>({}, std::move(entries));
        stack_ = {};
        longest_first_ = true;
    }

private:
    // 64 bits: the bits of the length as a float, which order as the lengths do for lengths
    // >= 0, then the edge (ties: the larger id first).
    static std::uint64_t entry(double length, int e) {
        return std::uint64_t{std::bit_cast<std::uint32_t>(static_cast<float>(length))} << 32 |
               static_cast<std::uint32_t>(e);
    }

    std::vector<int> stack_;
    std::priority_queue<std::uint64_t> heap_;
    bool longest_first_ = false;
};

// See FlipQueue: a loop whose flips outnumber its edges this many times goes longest first.
inline constexpr long long kFlipsPerEdgeBeforeLongestFirst = 4;

}  // namespace sdmesh::detail
