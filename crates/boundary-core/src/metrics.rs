use crate::CoreError;

/// Confusion matrix of a boundary classification against reference labels, where
/// "positive" means boundary.
///
/// Conventions for empty classes (stated because the papers do not): with no reference
/// boundary particle, Rec = 1 (nothing was missed); with no reference interior particle,
/// FPR = 0 (nothing could be wrongly flagged); with no predicted boundary particle,
/// precision = 1. Hence M = Rec·(1 − FPR) is always defined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Confusion {
    /// Boundary in both.
    pub tp: u64,
    /// Interior in both.
    pub tn: u64,
    /// Predicted boundary, reference interior.
    pub fp: u64,
    /// Predicted interior, reference boundary (a certified method has none).
    pub fn_: u64,
}

impl Confusion {
    /// Compares predicted labels with reference labels (`true` = boundary).
    pub fn from_labels(predicted: &[bool], truth: &[bool]) -> Result<Self, CoreError> {
        if predicted.len() != truth.len() {
            return Err(CoreError::LengthMismatch {
                predicted: predicted.len(),
                truth: truth.len(),
            });
        }
        let mut c = Confusion::default();
        for (&p, &t) in predicted.iter().zip(truth) {
            match (p, t) {
                (true, true) => c.tp += 1,
                (false, false) => c.tn += 1,
                (true, false) => c.fp += 1,
                (false, true) => c.fn_ += 1,
            }
        }
        Ok(c)
    }

    /// Number of particles compared.
    pub fn total(&self) -> u64 {
        self.tp + self.tn + self.fp + self.fn_
    }

    /// Recall Rec = TP / (TP + FN).
    pub fn recall(&self) -> f64 {
        ratio_or(self.tp, self.tp + self.fn_, 1.0)
    }

    /// False-positive rate FPR = FP / (FP + TN). (The JCP paper prints "FP/(P+TN)", a typo.)
    pub fn fpr(&self) -> f64 {
        ratio_or(self.fp, self.fp + self.tn, 0.0)
    }

    /// The papers' combined measure M = Rec · (1 − FPR).
    pub fn m(&self) -> f64 {
        self.recall() * (1.0 - self.fpr())
    }

    /// Precision TP / (TP + FP).
    pub fn precision(&self) -> f64 {
        ratio_or(self.tp, self.tp + self.fp, 1.0)
    }

    /// F1 = 2·precision·recall / (precision + recall), 0 when both are 0.
    pub fn f1(&self) -> f64 {
        let (p, r) = (self.precision(), self.recall());
        if p + r == 0.0 {
            0.0
        } else {
            2.0 * p * r / (p + r)
        }
    }
}

fn ratio_or(num: u64, den: u64, empty: f64) -> f64 {
    if den == 0 {
        empty
    } else {
        num as f64 / den as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_each_cell_of_the_matrix() {
        let pred = [true, true, false, false, true, false];
        let truth = [true, false, false, true, true, false];
        let c = Confusion::from_labels(&pred, &truth).unwrap();
        assert_eq!(
            c,
            Confusion {
                tp: 2,
                tn: 2,
                fp: 1,
                fn_: 1
            }
        );
        assert_eq!(c.total(), 6);
        assert!((c.recall() - 2.0 / 3.0).abs() < 1e-15);
        assert!((c.fpr() - 1.0 / 3.0).abs() < 1e-15);
        assert!((c.m() - 4.0 / 9.0).abs() < 1e-15);
        assert!((c.precision() - 2.0 / 3.0).abs() < 1e-15);
        assert!((c.f1() - 2.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn perfect_and_empty_cases_follow_the_stated_conventions() {
        let c = Confusion::from_labels(&[true, false], &[true, false]).unwrap();
        assert_eq!((c.recall(), c.fpr(), c.m(), c.f1()), (1.0, 0.0, 1.0, 1.0));
        let empty = Confusion::from_labels(&[], &[]).unwrap();
        assert_eq!((empty.recall(), empty.fpr(), empty.m()), (1.0, 0.0, 1.0));
        let all_wrong = Confusion::from_labels(&[false, true], &[true, false]).unwrap();
        assert_eq!(
            (all_wrong.recall(), all_wrong.fpr(), all_wrong.m()),
            (0.0, 1.0, 0.0)
        );
        assert_eq!(all_wrong.f1(), 0.0);
    }

    #[test]
    fn length_mismatch_is_an_error() {
        assert_eq!(
            Confusion::from_labels(&[true], &[true, false]),
            Err(CoreError::LengthMismatch {
                predicted: 1,
                truth: 2
            })
        );
    }
}
