// SPDX-License-Identifier: MIT
/// @brief SessionStateMachine: the OpenXR session life cycle without a runtime — which call each
///        reported state asks for, when frames are synchronised and rendered, exit requests,
///        loss, and invariants over seeded random event sequences.
#include <gtest/gtest.h>

#include <random>

#include "xr/openxr/session_state_machine.h"

namespace telesphere::xr {
namespace {

using S = openxr::SessionState;
using A = openxr::SessionAction;

TEST(SessionStateMachine, FullLifeCycleAsksForBeginAndEndAndFinishesOnExiting) {
  openxr::SessionStateMachine m;
  EXPECT_FALSE(m.running());
  EXPECT_FALSE(m.shouldSyncFrames());
  EXPECT_EQ(m.onStateChanged(S::kIdle), A::kNone);
  EXPECT_EQ(m.onStateChanged(S::kReady), A::kBeginSession);
  EXPECT_FALSE(m.shouldSyncFrames()) << "not before xrBeginSession succeeded";
  m.onSessionBegun();
  EXPECT_TRUE(m.running());
  EXPECT_TRUE(m.shouldSyncFrames()) << "READY after xrBeginSession: frames must be waited for";
  EXPECT_FALSE(m.shouldRender());
  EXPECT_EQ(m.onStateChanged(S::kSynchronized), A::kNone);
  EXPECT_TRUE(m.shouldSyncFrames());
  EXPECT_FALSE(m.shouldRender());
  EXPECT_EQ(m.onStateChanged(S::kVisible), A::kNone);
  EXPECT_TRUE(m.shouldRender());
  EXPECT_EQ(m.onStateChanged(S::kFocused), A::kNone);
  EXPECT_TRUE(m.shouldRender());
  EXPECT_EQ(m.onStateChanged(S::kVisible), A::kNone);
  EXPECT_EQ(m.onStateChanged(S::kSynchronized), A::kNone);
  EXPECT_FALSE(m.shouldRender());
  EXPECT_EQ(m.onStateChanged(S::kStopping), A::kEndSession);
  m.onSessionEnded();
  EXPECT_FALSE(m.running());
  EXPECT_FALSE(m.shouldSyncFrames());
  EXPECT_EQ(m.onStateChanged(S::kIdle), A::kNone);
  EXPECT_FALSE(m.finished()) << "IDLE without an exit request: the runtime may make us READY again";
  EXPECT_EQ(m.onStateChanged(S::kExiting), A::kDestroySession);
  EXPECT_TRUE(m.finished());
  EXPECT_FALSE(m.lost());
  const std::vector<S> expected{S::kIdle, S::kReady, S::kSynchronized, S::kVisible, S::kFocused,
                                S::kVisible, S::kSynchronized, S::kStopping, S::kIdle, S::kExiting};
  EXPECT_EQ(m.history(), expected);
  EXPECT_TRUE(m.reached(S::kFocused));
  EXPECT_FALSE(m.reached(S::kLossPending));
}

TEST(SessionStateMachine, ASecondReadyCycleBeginsAgain) {
  openxr::SessionStateMachine m;
  ASSERT_EQ(m.onStateChanged(S::kReady), A::kBeginSession);
  m.onSessionBegun();
  ASSERT_EQ(m.onStateChanged(S::kStopping), A::kEndSession);
  m.onSessionEnded();
  m.onStateChanged(S::kIdle);
  EXPECT_EQ(m.onStateChanged(S::kReady), A::kBeginSession);
}

TEST(SessionStateMachine, ExitRequestWhileRunningAsksTheRuntimeAndFinishesAfterStopping) {
  openxr::SessionStateMachine m;
  m.onStateChanged(S::kReady);
  m.onSessionBegun();
  m.onStateChanged(S::kFocused);
  EXPECT_EQ(m.requestExit(), A::kRequestExit);
  EXPECT_EQ(m.requestExit(), A::kNone) << "asked once only";
  EXPECT_TRUE(m.exitRequested());
  EXPECT_TRUE(m.shouldSyncFrames()) << "frames go on until the runtime stops the session";
  EXPECT_FALSE(m.finished());
  EXPECT_EQ(m.onStateChanged(S::kStopping), A::kEndSession);
  m.onSessionEnded();
  EXPECT_EQ(m.onStateChanged(S::kIdle), A::kDestroySession);
  EXPECT_TRUE(m.finished());
  EXPECT_EQ(m.onStateChanged(S::kExiting), A::kNone) << "already finished";
  EXPECT_EQ(m.onLost(), A::kNone) << "a loss after a clean end changes nothing";
  EXPECT_FALSE(m.lost());
}

TEST(SessionStateMachine, ExitRequestBeforeTheSessionRunsFinishesAtOnce) {
  openxr::SessionStateMachine m;
  m.onStateChanged(S::kIdle);
  EXPECT_EQ(m.requestExit(), A::kDestroySession);
  EXPECT_TRUE(m.finished());
  EXPECT_EQ(m.onStateChanged(S::kReady), A::kNone) << "no begin after the user quit";
}

TEST(SessionStateMachine, ReadyAfterAnExitRequestIsNotBegun) {
  // A runtime that skips IDLE and offers READY again: the user still wants out.
  openxr::SessionStateMachine n;
  n.onStateChanged(S::kReady);
  n.onSessionBegun();
  ASSERT_EQ(n.requestExit(), A::kRequestExit);
  n.onStateChanged(S::kStopping);
  n.onSessionEnded();
  EXPECT_EQ(n.onStateChanged(S::kReady), A::kDestroySession);
  EXPECT_TRUE(n.finished());
}

TEST(SessionStateMachine, FailedBeginLeavesTheSessionNotRunning) {
  openxr::SessionStateMachine m;
  ASSERT_EQ(m.onStateChanged(S::kReady), A::kBeginSession);
  m.onSessionBeginFailed();
  EXPECT_FALSE(m.running());
  EXPECT_FALSE(m.shouldSyncFrames());
}

TEST(SessionStateMachine, LossPendingEndsTheRunAndAsksForRecreation) {
  openxr::SessionStateMachine m;
  m.onStateChanged(S::kReady);
  m.onSessionBegun();
  m.onStateChanged(S::kFocused);
  EXPECT_EQ(m.onStateChanged(S::kLossPending), A::kRecreateSession);
  EXPECT_TRUE(m.lost());
  EXPECT_TRUE(m.finished());
  EXPECT_FALSE(m.running());
  EXPECT_FALSE(m.shouldSyncFrames());
  EXPECT_EQ(m.onLost(), A::kNone) << "reported once";
  EXPECT_EQ(m.requestExit(), A::kNone);
}

TEST(SessionStateMachine, InstanceLossStopsFramesAtOnce) {
  openxr::SessionStateMachine m;
  m.onStateChanged(S::kReady);
  m.onSessionBegun();
  m.onStateChanged(S::kVisible);
  ASSERT_TRUE(m.shouldRender());
  EXPECT_EQ(m.onLost(), A::kRecreateSession);
  EXPECT_FALSE(m.shouldRender());
  EXPECT_FALSE(m.shouldSyncFrames());
}

TEST(SessionStateMachine, StoppingWithoutARunningSessionNeedsNoEnd) {
  openxr::SessionStateMachine m;
  EXPECT_EQ(m.onStateChanged(S::kStopping), A::kNone);
}

TEST(SessionStateMachine, RepeatedStatesAreCollapsedInTheHistory) {
  openxr::SessionStateMachine m;
  m.onStateChanged(S::kIdle);
  m.onStateChanged(S::kIdle);
  m.onStateChanged(S::kReady);
  EXPECT_EQ(m.history(), (std::vector<S>{S::kIdle, S::kReady}));
}

TEST(SessionStateMachine, XrStateValuesAndNames) {
  const std::vector<std::pair<int, const char*>> known{
      {1, "IDLE"},     {2, "READY"},    {3, "SYNCHRONIZED"}, {4, "VISIBLE"},
      {5, "FOCUSED"},  {6, "STOPPING"}, {7, "LOSS_PENDING"}, {8, "EXITING"}};
  for (const auto& [value, name] : known) {
    EXPECT_EQ(openxr::sessionStateName(openxr::sessionStateFromXr(value)), name) << value;
  }
  EXPECT_EQ(openxr::sessionStateFromXr(0), S::kUnknown);
  EXPECT_EQ(openxr::sessionStateFromXr(9), S::kUnknown);
  EXPECT_EQ(openxr::sessionStateFromXr(0x7FFFFFFF), S::kUnknown);
  EXPECT_EQ(openxr::sessionStateName(S::kUnknown), "UNKNOWN");
  EXPECT_EQ(openxr::sessionActionName(A::kBeginSession), "begin session");
  EXPECT_EQ(openxr::sessionActionName(A::kRecreateSession), "recreate session");
}

// Invariants over seeded random sequences of runtime states, call results and user requests,
// with the owner doing what each action asks (as OpenXrSession does).
TEST(SessionStateMachine, RandomEventSequencesKeepTheInvariants) {
  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> pick(0, 11);
  for (int run = 0; run < 2000; ++run) {
    openxr::SessionStateMachine m;
    for (int step = 0; step < 40; ++step) {
      const int e = pick(rng);
      const bool was_running = m.running();
      const bool was_finished = m.finished();
      A a = A::kNone;
      if (e <= 8) a = m.onStateChanged(openxr::sessionStateFromXr(e));
      else if (e == 9) a = m.requestExit();
      else if (e == 10) a = m.onLost();
      else a = A::kNone;
      if (was_finished) { ASSERT_EQ(a, A::kNone) << "nothing is asked once finished"; }
      if (a == A::kBeginSession) {
        ASSERT_FALSE(was_running) << "begin only when not running";
        if (rng() & 1) m.onSessionBegun(); else m.onSessionBeginFailed();
      }
      if (a == A::kEndSession) {
        ASSERT_TRUE(was_running) << "end only a running session";
        m.onSessionEnded();
      }
      if (a == A::kRequestExit) { ASSERT_TRUE(was_running); }
      if (a == A::kDestroySession || a == A::kRecreateSession) { ASSERT_TRUE(m.finished()); }
      ASSERT_TRUE(!m.shouldRender() || m.shouldSyncFrames());
      ASSERT_TRUE(!m.shouldSyncFrames() || m.running());
      ASSERT_TRUE(!m.finished() || !m.shouldSyncFrames());
      ASSERT_TRUE(!m.lost() || m.finished());
      if (m.finished() && !was_finished) { ASSERT_NE(a, A::kNone) << "finishing always says so"; }
    }
  }
}

}  // namespace
}  // namespace telesphere::xr
