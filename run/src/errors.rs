//! An error's text as the command line prints it after `error: ` and as the Python package's
//! exceptions carry it.

/// What `decohesion` prints after `error: `: the message of `e` and of each of its causes,
/// joined by ": ", leaving out a cause whose message the text so far already ends with (see
/// [`causes_once`]).
pub fn error_message(e: &anyhow::Error) -> String {
    causes_once(e.chain())
}

/// The messages of an error and of its causes (`chain`, outermost first), joined by ": ",
/// leaving out a cause whose message the text so far already ends with. The errors of the
/// physics crate name their cause in their own message (`{file}: cannot read the scene file:
/// {source}`, so that the GUI shows it too), and joining every cause (anyhow's `{:#}`) printed
/// it twice: "… cannot read the scene file: No such file or directory (os error 2): No such
/// file or directory (os error 2)". The command line ([`error_message`]) and the Python
/// bindings' exceptions both build their text here, so that they stay the same words.
pub fn causes_once<'a>(
    chain: impl IntoIterator<Item = &'a (dyn std::error::Error + 'static)>,
) -> String {
    let mut text = String::new();
    for cause in chain {
        let m = cause.to_string();
        if text.is_empty() {
            text = m;
        } else if !text.ends_with(&m) {
            text.push_str(": ");
            text.push_str(&m);
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::error_message;
    use anyhow::Context;

    /// A scene file that cannot be read: the OS's reason once, after the file's name; a cause
    /// that the message does not contain is still printed after it.
    #[test]
    fn an_error_names_its_cause_once() {
        let e =
            decohesion_physics::scene::load_scene(std::path::Path::new("/no/such/scene.toml"), &[])
                .map_err(anyhow::Error::from)
                .unwrap_err();
        let m = error_message(&e);
        let reason = std::io::Error::from(std::io::ErrorKind::NotFound).to_string();
        assert!(
            m.starts_with("/no/such/scene.toml: cannot read the scene file: "),
            "{m}"
        );
        assert_eq!(m.matches("os error 2").count(), 1, "{m}");
        let wrapped = Err::<(), _>(std::io::Error::from(std::io::ErrorKind::NotFound))
            .context("writing out.rrd")
            .unwrap_err();
        assert_eq!(
            error_message(&wrapped),
            format!("writing out.rrd: {reason}")
        );
    }
}
