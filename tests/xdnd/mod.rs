//! A drag-and-drop source for the viewer's tests: drops a file on a window
//! the way a file manager does, by the XDND protocol (Enter, Position,
//! Drop, then the target asks for the `text/uri-list` selection, which
//! this answers). Only for Xvfb, where xdotool cannot drag files.

use std::path::Path;
use std::time::{Duration, Instant};

use x11rb::connection::Connection;
use x11rb::protocol::xproto::{
    ClientMessageEvent, ConnectionExt as _, CreateWindowAux, EventMask, PropMode, SelectionNotifyEvent, WindowClass, SELECTION_NOTIFY_EVENT,
};
use x11rb::protocol::Event;
use x11rb::wrapper::ConnectionExt as _;
use x11rb::{COPY_DEPTH_FROM_PARENT, CURRENT_TIME};

/// An X error as a message saying what failed.
fn fail<E: std::fmt::Display>(what: &'static str) -> impl FnOnce(E) -> String {
    move |e| format!("{what}: {e}")
}

/// Drops `file` on `window` at (x, y) in the window's pixels, and waits
/// until the window says it finished with it.
pub fn drop_file(window: u32, x: i16, y: i16, file: &Path) -> Result<(), String> {
    let (conn, screen) = x11rb::connect(None).map_err(fail("no X display"))?;
    let root = conn.setup().roots[screen].root;
    let atom = |name: &str| -> Result<u32, String> {
        Ok(conn.intern_atom(false, name.as_bytes()).map_err(fail("intern_atom"))?.reply().map_err(fail("intern_atom"))?.atom)
    };
    let [enter, position, status, drop, finished, selection, copy, uri_list] =
        ["XdndEnter", "XdndPosition", "XdndStatus", "XdndDrop", "XdndFinished", "XdndSelection", "XdndActionCopy", "text/uri-list"].map(atom);
    let (enter, position, status, drop, finished, selection, copy, uri_list) = (enter?, position?, status?, drop?, finished?, selection?, copy?, uri_list?);
    let source = conn.generate_id().map_err(fail("generate_id"))?;
    conn.create_window(COPY_DEPTH_FROM_PARENT, source, root, 0, 0, 1, 1, 0, WindowClass::INPUT_OUTPUT, 0, &CreateWindowAux::new())
        .map_err(fail("create_window"))?;
    conn.set_selection_owner(source, selection, CURRENT_TIME).map_err(fail("set_selection_owner"))?;
    let send = |kind: u32, data: [u32; 5]| -> Result<(), String> {
        conn.send_event(false, window, EventMask::NO_EVENT, ClientMessageEvent::new(32, window, kind, data))
            .map_err(fail("send_event"))?;
        conn.flush().map_err(fail("flush"))
    };
    let at = conn.translate_coordinates(window, root, x, y).map_err(fail("translate"))?.reply().map_err(fail("translate"))?;
    // Protocol version 5, one type (no XdndTypeList).
    send(enter, [source, 5 << 24, uri_list, 0, 0])?;
    send(position, [source, 0, ((at.dst_x as u32) << 16) | (at.dst_y as u32 & 0xffff), CURRENT_TIME, copy])?;
    let uri = format!("file://{}\r\n", file.display());
    let deadline = Instant::now() + Duration::from_secs(30);
    let mut dropped = false;
    while Instant::now() < deadline {
        let Some(event) = conn.poll_for_event().map_err(fail("poll"))? else {
            std::thread::sleep(Duration::from_millis(20));
            continue;
        };
        match event {
            Event::ClientMessage(m) if m.type_ == status && !dropped => {
                if m.data.as_data32()[1] & 1 == 0 {
                    return Err("the window refused the drop (XdndStatus without accept)".into());
                }
                send(drop, [source, 0, CURRENT_TIME, 0, 0])?;
                dropped = true;
            }
            Event::SelectionRequest(r) => {
                conn.change_property8(PropMode::REPLACE, r.requestor, r.property, r.target, uri.as_bytes())
                    .map_err(fail("change_property"))?;
                let notify = SelectionNotifyEvent {
                    response_type: SELECTION_NOTIFY_EVENT,
                    sequence: 0,
                    time: r.time,
                    requestor: r.requestor,
                    selection: r.selection,
                    target: r.target,
                    property: r.property,
                };
                conn.send_event(false, r.requestor, EventMask::NO_EVENT, notify).map_err(fail("send_event"))?;
                conn.flush().map_err(fail("flush"))?;
            }
            Event::ClientMessage(m) if m.type_ == finished => return Ok(()),
            _ => {}
        }
    }
    Err(format!("no XdndFinished from window {window} in 30 s (dropped: {dropped})"))
}
