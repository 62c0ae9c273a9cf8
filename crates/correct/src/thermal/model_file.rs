//! The model file `kezuri thermal fit` writes and `kezuri thermal apply`
//! reads (JSON): the error functions, and the axis letters of the
//! machine's tool and work chains they were fitted for.

use serde_json::{json, Value};

use super::{AxisError, ErrorModel, Polynomial};
use crate::kinematics::{Kinematics, AXES};
use crate::{Error, ErrorKind};

/// A model as its file holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelFile {
    /// The error functions.
    pub model: ErrorModel,
    /// The axis letters of the tool and the work chain of the machine it
    /// was fitted for.
    pub chains: [Vec<String>; 2],
}

impl ModelFile {
    /// Whether the machine `k` is the one the model was fitted for: the
    /// same axis letters in its tool and work chains.
    pub fn check_machine(&self, k: &Kinematics) -> Result<(), Error> {
        let here = chain_letters(k);
        if here == self.chains {
            return Ok(());
        }
        Err(Error::new(
            ErrorKind::OtherMachine,
            format!(
                "the model is for a machine with tool axes {:?} and work axes {:?}; this one (--machine) has {:?} and \
                 {:?}",
                self.chains[0], self.chains[1], here[0], here[1]
            ),
        ))
    }
}

/// The axis letters of the machine's tool and work chains, as a model
/// file names them.
pub fn chain_letters(k: &Kinematics) -> [Vec<String>; 2] {
    [&k.tool, &k.work].map(|axes| axes.iter().map(|x| AXES[x.index].to_string()).collect())
}

/// The model file of `model`, fitted to `measurements` measurements on
/// the machine `k`.
pub fn to_json(model: &ErrorModel, measurements: usize, k: &Kinematics) -> Value {
    let functions: Vec<Value> = model
        .functions
        .iter()
        .map(|f| {
            json!({
                "axis": AXES[f.axis].to_string(),
                "b_deg": f.b_deg,
                "degree": f.degree,
                "points": f.points,
                "center_mm": f.polynomial.center,
                "scale_mm": f.polynomial.scale,
                "coefficients_mm": f.polynomial.coefficients,
                "rms_mm": f.rms_mm,
            })
        })
        .collect();
    let [tool, work] = chain_letters(k);
    json!({
        "kezuri_thermal_model": 1,
        "measurements": measurements,
        "machine": {"tool": tool, "work": work, "tip": k.tip},
        "functions": functions,
    })
}

/// A model file's text back: the error functions and the chains they were
/// fitted for.
pub fn from_json(text: &str) -> Result<ModelFile, Error> {
    let v: Value = serde_json::from_str(text)
        .map_err(|e| Error::new(ErrorKind::NotAModel, format!("not a thermal model (JSON): {e}")))?;
    let bad = || Error::new(ErrorKind::NotAModel, "not a thermal model of kezuri thermal fit");
    if v["kezuri_thermal_model"] != 1 {
        return Err(bad());
    }
    let letters = |key: &str| -> Result<Vec<String>, Error> {
        v["machine"][key]
            .as_array()
            .ok_or_else(bad)?
            .iter()
            .map(|l| l.as_str().map(str::to_string).ok_or_else(bad))
            .collect()
    };
    let chains = [letters("tool")?, letters("work")?];
    let number = |x: &Value| x.as_f64().ok_or_else(bad);
    let mut functions = Vec::new();
    for f in v["functions"].as_array().ok_or_else(bad)? {
        let axis = ["X", "Y", "Z"].iter().position(|a| f["axis"] == *a).ok_or_else(bad)?;
        let coefficients: Vec<Vec<f64>> = f["coefficients_mm"]
            .as_array()
            .filter(|c| c.len() == 3)
            .ok_or_else(bad)?
            .iter()
            .map(|c| c.as_array().ok_or_else(bad)?.iter().map(number).collect::<Result<Vec<f64>, Error>>())
            .collect::<Result<_, Error>>()?;
        let rms: Vec<f64> = f["rms_mm"].as_array().ok_or_else(bad)?.iter().map(number).collect::<Result<_, Error>>()?;
        let [cx, cy, cz]: [Vec<f64>; 3] = coefficients.try_into().map_err(|_| bad())?;
        functions.push(AxisError {
            axis,
            b_deg: number(&f["b_deg"])?,
            polynomial: Polynomial {
                center: number(&f["center_mm"])?,
                scale: number(&f["scale_mm"])?,
                coefficients: [cx, cy, cz],
            },
            degree: f["degree"].as_u64().ok_or_else(bad)? as usize,
            rms_mm: [
                rms.first().copied().unwrap_or(0.0),
                rms.get(1).copied().unwrap_or(0.0),
                rms.get(2).copied().unwrap_or(0.0),
            ],
            points: f["points"].as_u64().unwrap_or(0) as usize,
        });
    }
    Ok(ModelFile { model: ErrorModel { functions }, chains })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::thermal::{fit, Measurement};

    #[test]
    fn a_model_comes_back_from_its_file() {
        let ms: Vec<Measurement> = (0..4)
            .map(|k| {
                let c = f64::from(k);
                Measurement { axis: 2, b_deg: 0.0, command: c, error: [0.001 * c, 0.0, 0.002 * c * c] }
            })
            .collect();
        let model = fit(&ms, Some(2)).unwrap();
        let k = Kinematics::mill();
        let v = to_json(&model, ms.len(), &k);
        assert_eq!(v["measurements"], 4);
        let back = from_json(&v.to_string()).unwrap();
        assert_eq!(back.chains, chain_letters(&k));
        back.check_machine(&k).unwrap();
        let e = back.check_machine(&Kinematics::mill_turn([0.0; 3], [0.0; 3])).unwrap_err();
        assert_eq!(e.kind, ErrorKind::OtherMachine);
        assert!(e
            .to_string()
            .starts_with(r#"the model is for a machine with tool axes ["X", "Y", "Z"] and work axes []"#));
        let back = back.model;
        assert_eq!(back.functions.len(), 1);
        let (f, g) = (&back.functions[0], &model.functions[0]);
        assert_eq!((f.axis, f.b_deg, f.degree, f.points), (g.axis, g.b_deg, g.degree, g.points));
        for c in [-1.0, 0.5, 3.0] {
            let (p, q) = (f.polynomial.at(c), g.polynomial.at(c));
            assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-15), "{p:?} {q:?}");
        }
    }

    #[test]
    fn what_is_not_a_model_says_so() {
        let e = from_json("nope").unwrap_err();
        assert_eq!(e.kind, ErrorKind::NotAModel);
        assert!(e.to_string().starts_with("not a thermal model (JSON): "), "{e}");
        let e = from_json(r#"{"kezuri_thermal_model": 2}"#).unwrap_err();
        assert_eq!(e.to_string(), "not a thermal model of kezuri thermal fit");
    }
}
