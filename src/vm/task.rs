//! Tasks: where each one is in which program, and what it waits for.

/// A place in a program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame {
    /// Index of the chunk (compiled program).
    pub chunk: usize,
    /// Next instruction.
    pub pc: u32,
    /// A MotionBASIC subroutine (`GOSUB`): `RETURN` comes back to the frame below.
    pub gosub: bool,
}

/// What a task is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TaskState {
    /// No program on it.
    Free,
    /// Runs at its next turn.
    Ready,
    /// Blocked on `Wait For`: the condition's code starts at `retry`; `resume` follows the wait.
    Waiting { retry: u32, resume: u32 },
    /// Blocked on `Wait For Time` until this update.
    Sleeping { until: u64 },
    /// Blocked on a motion initiate (or dwell) until the profile is free.
    MotionWait { profile: u8 },
}

/// One task.
#[derive(Debug, Clone)]
pub struct Task {
    /// Its state.
    pub state: TaskState,
    /// Call stack: the program it was started with first.
    pub frames: Vec<Frame>,
    /// The program started on it.
    pub program: u32,
    /// The next `DATA` constant its `READ` takes (0 when a program starts on it).
    pub data_at: u32,
}

impl Task {
    /// A free task.
    pub fn free() -> Task {
        Task {
            state: TaskState::Free,
            frames: Vec::new(),
            program: 0,
            data_at: 0,
        }
    }

    /// A task ready to run `chunk` from its start as `program`.
    pub fn starting(chunk: usize, program: u32) -> Task {
        Task {
            state: TaskState::Ready,
            frames: vec![Frame {
                chunk,
                pc: 0,
                gosub: false,
            }],
            program,
            data_at: 0,
        }
    }

    /// Has a program.
    pub fn busy(&self) -> bool {
        self.state != TaskState::Free
    }
}
